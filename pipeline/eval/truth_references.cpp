#include "pipeline/eval/truth_references.h"

#include <algorithm>

#include "pipeline/networks/view_slots.h"
#include "pipeline/preset.h"
#include "runtime/error.h"

namespace smokesvd::eval {

TruthReferences::TruthReferences(const ReconstructionRun& run, TruthScene truth, const std::vector<int>& selected,
                                 Units units)
    : run_(run), truth_(std::move(truth)), units_(units) {
  const GridSize& g = truth_.scene.resolution;
  if (g != run.grid)
    throw Error(truth_.folder.string() + ": the truth is " + std::to_string(g.x) + "x" + std::to_string(g.y) + "x" +
                std::to_string(g.z) + " cells, the reconstruction " + std::to_string(run.grid.x) + "x" +
                std::to_string(run.grid.y) + "x" + std::to_string(run.grid.z) + " (x, y, z); evaluate against a truth of the reconstruction's resolution");
  if (truth_.frames < run.firstFrame + run.frames)
    throw Error(truth_.folder.string() + ": the truth has " + std::to_string(truth_.frames) +
                " frames, the reconstruction covers input frames " + std::to_string(run.firstFrame) + " to " +
                std::to_string(run.firstFrame + run.frames - 1));
  if (run.framing != reconstruct::Framing::Box)
    throw Error(run.folder.string() + ": evaluating against a truth needs a reconstruction made with --framing box "
                "(the whole frame as the box's front view), so that its box is the truth's");
  const Preset& preset = smokesvd::preset(run.preset);
  std::vector<int> slots = selected;
  if (slots.empty())
    for (int s = 0; s < networks::kSlots; ++s) slots.push_back(s);
  for (int s : slots)
    if (s < 0 || s >= networks::kSlots)
      throw Error("--views: orbit views are 0 to " + std::to_string(networks::kSlots - 1) + ", got " + std::to_string(s));
  if (std::find(slots.begin(), slots.end(), networks::kFrontSlot) == slots.end()) slots.insert(slots.begin(), networks::kFrontSlot);
  std::sort(slots.begin(), slots.end());
  slots.erase(std::unique(slots.begin(), slots.end()), slots.end());
  for (int s : slots) {
    EvalView view;
    char name[16];
    std::snprintf(name, sizeof name, "view_%02d", s);
    view.name = name;
    view.group = s == networks::kFrontSlot ? ViewGroup::Input : s == networks::kSideSlot ? ViewGroup::Side : ViewGroup::Novel;
    const double angle = networks::slotAngle(s);
    view.camera = networks::orbitCameraAt(preset, angle);
    view.mirroredInputFloor = angle >= 90.0;
    view.description = {{"camera", "orbit, orthographic"},
                        {"angle_degrees", angle},
                        {"region", "the orbit window: the box's x extent by its y extent, centred on the box"},
                        {"resolution", {preset.imageWidth, preset.imageHeight}}};
    views_.push_back(view);
  }
}

std::vector<media::Image> TruthReferences::raw(Context& context, int t) const {
  return renderViews(context, truth_.density(truthFrame(t), run_.absorption), run_.grid, views_, run_.look());
}

std::vector<media::Image> TruthReferences::frame(Context& context, int t) {
  std::vector<media::Image> images = raw(context, t);
  if (run_.mapping.perPixelBackground && background_.empty()) background_ = t == 0 ? images : raw(context, 0);
  if (units_ == Units::Mapped)
    for (std::size_t v = 0; v < images.size(); ++v)
      mapIntensity(images[v], run_.mapping, background_.empty() ? nullptr : &background_[v]);
  return images;
}

void TruthReferences::toUnits(std::size_t view, media::Image& render) const {
  if (units_ == Units::Footage) mapBack(render, run_.mapping, background_.empty() ? nullptr : &background_[view]);
}

nlohmann::json TruthReferences::describe() const {
  return {{"kind", "truth"},
          {"scene", std::filesystem::absolute(truth_.folder).string()},
          {"truth_frames", {truthFrame(0), truthFrame(run_.frames - 1)}},
          {"look", {{"absorption", run_.absorption}, {"ambient", 1}, {"light", "none"}}},
          {"density_units", "the networks' units of the box: truth density * " + std::to_string(truth_.scene.render.absorption) +
                                " / " + std::to_string(run_.absorption)}};
}

}  // namespace smokesvd::eval
