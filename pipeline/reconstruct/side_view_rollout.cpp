#include "pipeline/reconstruct/side_view_rollout.h"

#include <algorithm>
#include <numeric>
#include <optional>

#include "pipeline/dataset/synthesised_side_views.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/media/image.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/progress.h"
#include "pipeline/render/render_images.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

double average(const std::vector<double>& v, std::size_t begin, std::size_t end) {
  end = std::min(end, v.size());
  if (begin >= end) return 0;
  return std::accumulate(v.begin() + static_cast<std::ptrdiff_t>(begin), v.begin() + static_cast<std::ptrdiff_t>(end), 0.0) /
         static_cast<double>(end - begin);
}

dataset::SideViewRolloutManifest manifestOf(const Preset& preset, int firstFrame, int frames, const SideViewOptions& o,
                                            RolloutHistory history) {
  dataset::SideViewRolloutManifest m;
  m.preset = preset.name;
  m.firstFrame = firstFrame;
  m.frames = frames;
  m.height = preset.imageHeight;
  m.width = preset.imageWidth;
  m.how = {{"history", history == RolloutHistory::Truth ? "truth" : "own"},
           {"sampling",
            {{"synthesize", o.synthesize}, {"steps", o.steps}, {"init_steps", o.initSteps}, {"eta", o.eta}, {"start", o.start},
             {"seed", o.seed}, {"samples", o.samples}, {"init_share", o.initShare}}}};
  return m;
}

}  // namespace

double RolloutResult::mean() const { return average(psnr, 0, psnr.size()); }
double RolloutResult::mirroredMean() const { return average(mirrored, 0, mirrored.size()); }
double RolloutResult::blackMean() const { return average(black, 0, black.size()); }
double RolloutResult::previousMean() const { return average(previous, 0, previous.size()); }
double RolloutResult::firstTen() const { return average(psnr, 0, 10); }
double RolloutResult::lastTen() const { return average(psnr, psnr.size() >= 10 ? psnr.size() - 10 : 0, psnr.size()); }
double RolloutResult::mirroredFirstTen() const { return average(mirrored, 0, 10); }
double RolloutResult::mirroredLastTen() const {
  return average(mirrored, mirrored.size() >= 10 ? mirrored.size() - 10 : 0, mirrored.size());
}

nlohmann::json RolloutResult::toJson() const {
  return {{"scenes", scenes},
          {"history", trueHistory ? "truth" : "own"},
          {"first_frame", firstFrame},
          {"frames", psnr.size()},
          {"psnr_mean", mean()},
          {"psnr_mirrored_front_mean", mirroredMean()},
          {"psnr_black_mean", blackMean()},
          {"psnr_previous_true_side_mean", previousMean()},
          {"psnr_first_10", firstTen()},
          {"psnr_last_10", lastTen()},
          {"psnr_mirrored_front_first_10", mirroredFirstTen()},
          {"psnr_mirrored_front_last_10", mirroredLastTen()},
          {"psnr_per_frame", psnr},
          {"psnr_mirrored_front_per_frame", mirrored},
          {"psnr_black_per_frame", black},
          {"psnr_previous_true_side_per_frame_from_1", previous}};
}

RolloutResult sideViewRollout(Context& context, MethodModels& models, const dataset::SceneDataset& data, int firstFrame,
                              int frames, int scenes, const SideViewOptions& options, RolloutHistory history, bool progress,
                              const RolloutScenes& from) {
  const Preset& preset = data.preset();
  std::vector<const dataset::SceneEntry*> rolled;  // the first `scenes` scenes of the split with enough frames
  for (const dataset::SceneEntry& scene : from.training ? data.training() : data.validation())
    if (scene.frames >= firstFrame + frames && static_cast<int>(rolled.size()) < scenes) rolled.push_back(&scene);
  if (rolled.empty())
    throw Error(data.root().string() + ": no " + (from.training ? "training" : "validation") + " scene has the " +
                std::to_string(firstFrame + frames) +
                " frames of a rollout of " + std::to_string(frames) + " frames from frame " + std::to_string(firstFrame));
  const auto rolledScenes = static_cast<int64_t>(rolled.size());
  Progress bar(rolledScenes * frames, 0, frames, !progress);  // off a terminal, a line per scene
  RolloutResult result;
  result.trueHistory = history == RolloutHistory::Truth;
  result.firstFrame = firstFrame;
  result.psnr.assign(static_cast<std::size_t>(frames), 0.0);
  result.mirrored.assign(static_cast<std::size_t>(frames), 0.0);
  result.black.assign(static_cast<std::size_t>(frames), 0.0);
  result.previous.assign(static_cast<std::size_t>(frames - 1), 0.0);
  const std::vector<Camera> frontSide{networks::orbitCameraAt(preset, 0), networks::orbitCameraAt(preset, 90)};
  const render::ViewSet sideCamera = render::uploadViews(context, std::vector<Camera>{frontSide[1]});
  const dataset::SideViewRolloutManifest manifest = manifestOf(preset, firstFrame, frames, options, history);
  const bool keep = !from.keepSideViews.empty();
  if (keep) dataset::prepareSideViewFolder(from.keepSideViews, manifest);
  for (const dataset::SceneEntry* rolledScene : rolled) {
    const dataset::SceneEntry& scene = *rolledScene;
    const render::RenderSettings look = data.look(scene);
    std::vector<media::Image> fronts, sides;
    for (int t = 0; t < frames; ++t) {
      const auto images = render::renderImages(context, Tensor::fromHost(context, preset.grid.volume(), data.density(scene, firstFrame + t)),
                                               frontSide, look);
      fronts.push_back(images[0]);
      sides.push_back(images[1]);
    }
    // Side views kept by an earlier rollout into the same folder are this one's: it is deterministic.
    const std::optional<std::vector<float>> kept = keep ? dataset::readSceneSideViews(from.keepSideViews, manifest, scene) : std::nullopt;
    std::vector<float> synthesizedFrames;  // what this rollout keeps of the scene
    FrameState state(context, preset);
    const Shape image{1, 1, preset.imageHeight, preset.imageWidth};
    // Frame t's side view, and the history of the frames after it: that side view (or with true history the
    // true one) and the side render of its coarse density.
    auto synthesizeFrame = [&](int t) {
      const Tensor front = Tensor::fromHost(context, image, fronts[static_cast<std::size_t>(t)].values);
      const Tensor next = Tensor::fromHost(context, image, fronts[static_cast<std::size_t>(std::min(t + 1, frames - 1))].values);
      const Tensor side = sideView(context, models, state, t, front, next, options);
      const Tensor conditioning = result.trueHistory ? Tensor::fromHost(context, image, sides[static_cast<std::size_t>(t)].values) : side;
      Stream stream(context);
      Tape tape(stream);
      NoGrad noGrad(tape);
      const Var coarse = models.coarse->forward(tape,
                                                models.coarse->slotImages(tape, {{networks::kFrontSlot, variable(front)},
                                                                                 {networks::kSideSlot, variable(conditioning)}}),
                                                variable(Tensor::fromHost(context, {networks::kSlots}, [] {
                                                  std::vector<float> p(networks::kSlots, 0.0f);
                                                  p[networks::kFrontSlot] = p[networks::kSideSlot] = 1.0f;
                                                  return p;
                                                }())))
                             .density;
      const Var render = diff::render(tape, coarse, sideCamera, look);
      stream.copy(state.side1, state.side2);
      stream.copy(state.sideRender1, state.sideRender2);
      stream.copy(conditioning, state.side1);
      stream.copy(render->value, state.sideRender1);
      stream.submit();
      return side.download();
    };
    for (int t = 0; t < frames; ++t) {
      const std::vector<float> synthesized = kept ? dataset::sideViewAt(*kept, manifest, t) : synthesizeFrame(t);
      if (keep && !kept) synthesizedFrames.insert(synthesizedFrames.end(), synthesized.begin(), synthesized.end());
      const std::vector<float> mirror = media::mirroredRows(fronts[static_cast<std::size_t>(t)].values, preset.imageWidth);
      result.psnr[static_cast<std::size_t>(t)] += train::psnr(synthesized, sides[static_cast<std::size_t>(t)].values);
      result.mirrored[static_cast<std::size_t>(t)] += train::psnr(mirror, sides[static_cast<std::size_t>(t)].values);
      result.black[static_cast<std::size_t>(t)] +=
          train::psnr(std::vector<float>(synthesized.size(), 0.0f), sides[static_cast<std::size_t>(t)].values);
      if (t > 0)
        result.previous[static_cast<std::size_t>(t - 1)] +=
            train::psnr(sides[static_cast<std::size_t>(t - 1)].values, sides[static_cast<std::size_t>(t)].values);
      bar.update(static_cast<int64_t>(result.scenes) * frames + t + 1,
                 "scene " + std::to_string(result.scenes + 1) + "/" + std::to_string(rolledScenes) +
                     " frame " + std::to_string(t));
    }
    if (keep && !kept) dataset::writeSceneSideViews(from.keepSideViews, manifest, scene, synthesizedFrames);
    ++result.scenes;
  }
  bar.finish();
  for (double& v : result.psnr) v /= result.scenes;
  for (double& v : result.mirrored) v /= result.scenes;
  for (double& v : result.black) v /= result.scenes;
  for (double& v : result.previous) v /= result.scenes;
  return result;
}

}  // namespace smokesvd::reconstruct
