#include "pipeline/eval/evaluation.h"

#include <cmath>
#include <memory>

#include "nets/io/file_io.h"
#include "nets/io/json_file.h"
#include "pipeline/eval/comparison_sheet.h"
#include "pipeline/eval/fields.h"
#include "pipeline/eval/metric_tally.h"
#include "pipeline/eval/truth_references.h"
#include "pipeline/eval/volume_metrics.h"
#include "pipeline/progress.h"
#include "runtime/error.h"

namespace smokesvd::eval {
namespace fs = std::filesystem;
namespace {

using nlohmann::json;

std::vector<int> slotNumbers(const std::vector<std::string>& names) {
  std::vector<int> slots;
  for (const std::string& name : names) {
    std::size_t used = 0;
    int slot = -1;
    try {
      slot = std::stoi(name, &used);
    } catch (const std::logic_error&) {
      used = 0;
    }
    if (used != name.size() || name.empty())
      throw Error("--views: against a truth, views are orbit slot numbers 0 to 15, got '" + name + "'");
    slots.push_back(slot);
  }
  return slots;
}

std::unique_ptr<References> makeReferences(const ReconstructionRun& run, const EvalOptions& o) {
  const bool truth = !o.truth.empty(), footage = !o.cameras.empty() || !o.videos.empty();
  if (truth == footage) throw Error("eval: give either --truth SCENE_DIR or --cameras info.json with --videos DIR");
  if (truth) return std::make_unique<TruthReferences>(run, readTruthScene(o.truth), slotNumbers(o.views), o.units);
  if (o.cameras.empty() || o.videos.empty()) throw Error("eval: --cameras and --videos go together");
  FootageOptions f;
  f.calibration = o.cameras;
  f.videos = o.videos;
  f.selected = o.views;
  f.region = o.region;
  f.width = o.width;
  f.supersample = o.supersample;
  f.units = o.units;
  return std::make_unique<FootageReferences>(run, f);
}

// The input view's reference as view `view` (mirrored where it says, resized to its size).
media::Image inputFloor(const media::Image& input, const EvalView& view) {
  media::Image image = view.mirroredInputFloor ? mirrored(input) : input;
  if (image.width != view.camera.width || image.height != view.camera.height)
    image = media::resize(image, view.camera.width, view.camera.height);
  clampUnit(image);
  return image;
}

// Which views the sheet shows: all with a reference if they are at most 6, else those nearest 0, 45, 90 and 135 deg.
std::vector<std::size_t> sheetViews(const std::vector<EvalView>& views) {
  std::vector<std::size_t> withReference;
  for (std::size_t v = 0; v < views.size(); ++v)
    if (views[v].hasReference) withReference.push_back(v);
  if (withReference.size() <= 6) return withReference;
  std::vector<std::size_t> chosen;
  for (double target : {0.0, 45.0, 90.0, 135.0}) {
    std::size_t best = withReference[0];
    for (std::size_t v : withReference)
      if (std::abs(views[v].description["angle_degrees"].get<double>() - target) <
          std::abs(views[best].description["angle_degrees"].get<double>() - target))
        best = v;
    if (std::find(chosen.begin(), chosen.end(), best) == chosen.end()) chosen.push_back(best);
  }
  return chosen;
}

std::string csvLine(const std::vector<std::string>& cells) {
  std::string line;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const bool quote = cells[i].find_first_of(",\"") != std::string::npos;
    std::string cell = cells[i];
    if (quote) {
      std::string escaped;
      for (char c : cell) escaped += c == '"' ? std::string("\"\"") : std::string(1, c);
      cell = "\"" + escaped + "\"";
    }
    line += (i ? "," : "") + cell;
  }
  return line + "\n";
}

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

}  // namespace

json runEvaluation(Context& context, const EvalOptions& o) {
  if (o.out.empty()) throw Error("eval: --out is required");
  if (o.sheetFrames < 1) throw Error("--sheet-frames: expected at least 1");
  const ReconstructionRun run = readReconstructionRun(o.reconstruction);
  const std::unique_ptr<References> references = makeReferences(run, o);
  const TruthReferences* truth = dynamic_cast<const TruthReferences*>(references.get());
  const std::vector<EvalView>& views = references->views();
  std::size_t input = 0;
  for (std::size_t v = 0; v < views.size(); ++v)
    if (views[v].group == ViewGroup::Input) input = v;
  std::error_code error;
  fs::create_directories(o.out, error);
  if (error || !fs::is_directory(o.out)) throw Error(o.out.string() + ": cannot create the output folder (" + error.message() + ")");

  std::vector<ViewTally> tallies(views.size());
  VolumeTally volume;
  volume.truth = truth != nullptr;
  const std::vector<int> shownFrames = sheetFrames(run.frames, o.sheetFrames);
  const std::vector<std::size_t> shownViews = sheetViews(views);
  std::vector<SheetRow> sheet(shownViews.size());
  std::string perFrame = csvLine({"frame", "view", "group", "ours_rmse", "ours_psnr", "ours_ssim", "floor_black_rmse",
                                  "floor_black_psnr", "floor_black_ssim", "floor_input_rmse", "floor_input_psnr", "floor_input_ssim"});
  Progress progress(run.frames, 0, 1, o.quiet);
  for (int t = 0; t < run.frames; ++t) {
    const std::vector<float> density = run.density(t);
    const std::vector<media::Image> reference = references->frame(context, t);
    std::vector<media::Image> ours = renderViews(context, density, run.grid, views, run.look());
    for (std::size_t v = 0; v < views.size(); ++v) references->toUnits(v, ours[v]);

    std::vector<media::Image> black, floorInput(views.size());
    for (const EvalView& view : views) black.push_back(media::Image::gray(view.camera.width, view.camera.height));
    std::vector<ImagePair> pairs;
    std::vector<std::pair<std::size_t, int>> owners;  // (view, candidate) of each pair
    for (std::size_t v = 0; v < views.size(); ++v) {
      if (!views[v].hasReference) continue;
      pairs.push_back({&ours[v], &reference[v]});
      owners.emplace_back(v, kOurs);
      pairs.push_back({&black[v], &reference[v]});
      owners.emplace_back(v, kFloorBlack);
      if (v != input) {
        floorInput[v] = inputFloor(reference[input], views[v]);
        pairs.push_back({&floorInput[v], &reference[v]});
        owners.emplace_back(v, kFloorInput);
      }
    }
    const std::vector<ImageScore> scores = compareImages(context, pairs);
    std::vector<std::array<std::string, 9>> rows(views.size());
    for (std::size_t i = 0; i < scores.size(); ++i) {
      const auto [v, candidate] = owners[i];
      tallies[v].image[static_cast<std::size_t>(candidate)].add(scores[i]);
      rows[v][3 * candidate] = number(scores[i].rmse());
      rows[v][3 * candidate + 1] = number(scores[i].psnr());
      rows[v][3 * candidate + 2] = number(scores[i].ssim);
    }
    for (std::size_t v = 0; v < views.size(); ++v) {
      tallies[v].temporal[kSequenceOurs].add(ours[v]);
      if (!views[v].hasReference) continue;
      tallies[v].temporal[kSequenceReference].add(reference[v]);
      tallies[v].temporal[kSequenceBlack].add(black[v]);
      if (v != input) tallies[v].temporal[kSequenceInput].add(floorInput[v]);
      std::vector<std::string> line{std::to_string(t), views[v].name, groupName(views[v].group)};
      line.insert(line.end(), rows[v].begin(), rows[v].end());
      perFrame += csvLine(line);
    }
    if (std::find(shownFrames.begin(), shownFrames.end(), t) != shownFrames.end())
      for (std::size_t r = 0; r < shownViews.size(); ++r) {
        sheet[r].reference.push_back(reference[shownViews[r]]);
        sheet[r].ours.push_back(ours[shownViews[r]]);
      }

    if (truth) {
      const Tensor ours3 = Tensor::fromHost(context, run.grid.volume(), density);
      const Tensor truth3 = Tensor::fromHost(context, run.grid.volume(), truth->truth().density(truth->truthFrame(t), run.absorption));
      const Tensor zero = Tensor::fromHost(context, run.grid.volume(), std::vector<float>(density.size(), 0.0f));
      volume.densityOurs += densityRmse(context, ours3, truth3);
      volume.densityZero += densityRmse(context, zero, truth3);
      ++volume.densityFrames;
    }
    if (t < run.frames - 1 || run.frames == 1) {
      const Tensor u = Tensor::fromHost(context, run.grid.vector(), run.velocity(t));
      const VelocityScores s = velocityScores(context, u);
      volume.divergenceOurs += s.meanAbsDivergence;
      volume.gradientOurs += s.meanGradientSquared;
      if (truth) {
        const Tensor uTruth = Tensor::fromHost(context, run.grid.vector(), truth->truth().velocity(truth->truthFrame(t)));
        const Tensor zero(context, run.grid.vector());
        Stream stream(context);
        stream.fillZero(zero);
        stream.submit();
        const VelocityScores st = velocityScores(context, uTruth);
        volume.divergenceTruth += st.meanAbsDivergence;
        volume.gradientTruth += st.meanGradientSquared;
        volume.velocityOurs += velocityRmse(context, u, uTruth);
        volume.velocityZero += velocityRmse(context, zero, uTruth);
        ++volume.velocityFrames;
      }
      ++volume.motionFrames;
    }
    progress.update(t + 1, "frame " + std::to_string(t));
  }
  progress.finish();

  const std::string units = o.units == Units::Mapped ? "mapped" : "footage";
  const Summary summary = summarise(views, tallies, volume, units);
  json viewList = json::array();
  for (const EvalView& view : views) {
    json entry = view.description;
    entry["name"] = view.name;
    entry["group"] = groupName(view.group);
    entry["has_reference"] = view.hasReference;
    entry["supersample"] = view.supersample;
    entry["input_floor"] = view.group == ViewGroup::Input || !view.hasReference ? json(nullptr)
                           : view.mirroredInputFloor ? json("the input view mirrored left-right")
                                                     : json("the input view as it is");
    viewList.push_back(entry);
  }
  json metrics = {
      {"command", "smokesvd eval"},
      {"reconstruction", {{"folder", fs::absolute(run.folder).string()}, {"preset", run.preset}, {"models", run.models},
                          {"frames", run.frames}, {"first_input_frame", run.firstFrame},
                          {"grid", {run.grid.x, run.grid.y, run.grid.z}}}},
      {"reference", references->describe()},
      {"units", units == "mapped"
                    ? "the networks' units: references through the reconstruction's intensity mapping, renders as they are"
                    : "the footage's units: references as they are, renders mapped back by black + w / gain"},
      {"intensity_mapping", {{"black", run.mapping.black}, {"gain", run.mapping.gain}, {"threshold", run.mapping.threshold},
                             {"per_pixel_background", run.mapping.perPixelBackground}}},
      {"views", viewList},
      {"image", summary.image},
      {"temporal", summary.temporal},
      {"volume", summary.volume},
      {"not_computed",
       {{"LPIPS", "needs a pretrained image network (AlexNet/VGG features), which cannot be obtained here"},
        {"FID", "needs the pretrained Inception network"},
        {"STYLE", "needs the pretrained VGG19 network (Gram matrices of its features)"}}},
      {"sheet", {{"file", "comparison.png"}, {"frames", shownFrames}, {"columns", "reference | ours | error, per frame"},
                 {"error", "d = ours - reference: red where ours is brighter, blue where darker, full at |d| >= 0.5"}}}};
  json sheetViewNames = json::array();
  for (std::size_t v : shownViews) sheetViewNames.push_back(views[v].name);
  metrics["sheet"]["views"] = sheetViewNames;

  io::writeJsonFile(o.out / "metrics.json", metrics);
  std::string csv = csvLine(metricsCsvHeader());
  for (const auto& row : summary.csvRows) csv += csvLine(row);
  io::writeTextFileAtomically(o.out / "metrics.csv", csv);
  io::writeTextFileAtomically(o.out / "per_frame.csv", perFrame);
  if (!shownViews.empty()) {
    for (std::size_t r = 0; r < shownViews.size(); ++r) {
      const EvalView& view = views[shownViews[r]];
      char label[128];
      std::snprintf(label, sizeof label, "%s  %.1f deg  %dx%d", view.name.c_str(), view.description["angle_degrees"].get<double>(),
                    view.camera.width, view.camera.height);
      sheet[r].label = label;
    }
    const std::string caption = fs::absolute(run.folder).filename().string() + " against " +
                                (truth ? "the truth " + fs::absolute(o.truth).filename().string() : "the footage of " + o.cameras.filename().string()) +
                                ", " + units + " units";
    media::writePng(o.out / "comparison.png", comparisonSheet(caption, shownFrames, sheet));
  }
  return metrics;
}

}  // namespace smokesvd::eval
