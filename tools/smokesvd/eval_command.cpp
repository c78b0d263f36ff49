// `smokesvd eval RECON_DIR (--truth SCENE_DIR | --cameras info.json --videos DIR) --out DIR`: image, volume and
// temporal metrics of a reconstruction, each beside its trivial floors (docs/evaluation.md):
//
//   smokesvd eval recon/ --truth scenes/scene_0009 --out eval/               16 orbit views, volumes, motion
//   smokesvd eval recon/ --truth scene/ --views 0,4,8,12 --out eval/
//   smokesvd eval recon/ --cameras info.json --videos scalarflow/ --out eval/  the calibrated cameras, box crops
//   smokesvd eval recon/ --cameras info.json --videos scalarflow/ --region frame --width 270 --out eval/
#include <iostream>
#include <sstream>

#include "pipeline/eval/evaluation.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct EvalArguments {
  std::string reconstruction, truth, cameras, videos, out, views, region = "box", units = "mapped";
  int width = 270, supersample = 2, sheetFrames = 3;
  bool quiet = false;
};

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
    if (!item.empty()) items.push_back(item);
  return items;
}

std::string figure(const nlohmann::json& value, const char* format) {
  if (value.is_null()) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, value.get<double>());
  return buffer;
}

void printSummary(const nlohmann::json& metrics) {
  for (const char* group : {"input", "side", "novel"}) {
    if (!metrics["image"].contains(group)) continue;
    const nlohmann::json& g = metrics["image"][group];
    std::cout << group << ": PSNR " << figure(g["psnr"]["ours"], "%.2f") << " dB (floors: black "
              << figure(g["psnr"]["floor_black"], "%.2f") << ", input view " << figure(g["psnr"]["floor_input"], "%.2f")
              << "), SSIM " << figure(g["ssim"]["ours"], "%.3f") << " (" << figure(g["ssim"]["floor_black"], "%.3f") << ", "
              << figure(g["ssim"]["floor_input"], "%.3f") << "), RMSE " << figure(g["rmse"]["ours"], "%.4f") << "\n";
  }
  const nlohmann::json& v = metrics["volume"];
  if (!v["density_rmse"]["ours"].is_null())
    std::cout << "volume: density RMSE " << figure(v["density_rmse"]["ours"], "%.4g") << " (zero: "
              << figure(v["density_rmse"]["floor_zero"], "%.4g") << "), velocity RMSE " << figure(v["velocity_rmse"]["ours"], "%.4g")
              << " (zero: " << figure(v["velocity_rmse"]["floor_zero"], "%.4g") << ")\n";
  std::cout << "motion: mean |div u| " << figure(v["mean_abs_divergence"]["ours"], "%.4g") << " (truth "
            << figure(v["mean_abs_divergence"]["truth"], "%.4g") << "), mean |grad u|^2 "
            << figure(v["mean_gradient_squared"]["ours"], "%.4g") << " (truth " << figure(v["mean_gradient_squared"]["truth"], "%.4g")
            << ")\n";
}

void runEval(const GlobalOptions& global, const EvalArguments& a) {
  eval::EvalOptions o;
  o.reconstruction = a.reconstruction;
  o.truth = a.truth;
  o.cameras = a.cameras;
  o.videos = a.videos;
  o.out = a.out;
  o.views = splitList(a.views);
  o.region = eval::parseRegion(a.region);
  o.width = a.width;
  o.supersample = a.supersample;
  o.units = eval::parseUnits(a.units);
  o.sheetFrames = a.sheetFrames;
  o.quiet = a.quiet;
  Context context(global.contextOptions());
  const nlohmann::json metrics = eval::runEvaluation(context, o);
  printSummary(metrics);
  std::cerr << a.out << ": metrics.json, metrics.csv, per_frame.csv, comparison.png\n";
}

void addEvalCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static EvalArguments a;
  CLI::App* c = app.add_subcommand("eval", "measure a reconstruction against a simulated truth or calibrated footage, beside the trivial floors");
  c->add_option("reconstruction", a.reconstruction, "the folder of a finished smokesvd reconstruct run")->required();
  c->add_option("--out", a.out, "output folder: metrics.json, metrics.csv, per_frame.csv, comparison.png")->required();
  CLI::Option* truth = c->add_option("--truth", a.truth, "a smokesvd simulate scene folder (the reconstruction made with --framing box from its front view)");
  CLI::Option* cameras = c->add_option("--cameras", a.cameras, "a NeRF-style info.json (the reconstruction made with --camera of the same file)");
  CLI::Option* videos = c->add_option("--videos", a.videos, "the folder of the calibration's videos");
  c->add_option("--views", a.views, "orbit slots 0-15 (truth) or camera names (footage), comma-separated; default all (the input view always)");
  CLI::Option* region = c->add_option("--region", a.region, "footage: box (the box's projection at the preset's image size, default) or frame (whole frames)")
                            ->check(CLI::IsMember({"box", "frame"}));
  c->add_option("--width", a.width, "footage --region frame: image width in pixels (default 270)")
      ->check(wholeNumber(1, kMaxImageSide))
      ->needs(region);
  CLI::Option* supersample = c->add_option("--supersample", a.supersample, "footage: rays per pixel along each axis, averaged (default 2)")
                                 ->check(wholeNumber(1, 16));
  c->add_option("--units", a.units, "mapped (references through the input's intensity mapping, default) or footage (renders mapped back)")
      ->check(CLI::IsMember({"mapped", "footage"}));
  c->add_option("--sheet-frames", a.sheetFrames, "frames on the comparison sheet (default 3)")->check(wholeNumber(1, 100));
  c->add_flag("--quiet", a.quiet, "no progress line");
  // Either a simulated truth or calibrated footage (its cameras and its videos).
  truth->excludes(cameras)->excludes(videos)->excludes(region)->excludes(supersample);
  cameras->needs(videos);
  videos->needs(cameras);
  c->callback([&global, &action, truth, cameras] {
    if (truth->count() == 0 && cameras->count() == 0)
      throw CLI::RequiredError("give either --truth SCENE_DIR or --cameras info.json with --videos DIR",
                               CLI::ExitCodes::RequiredError);
    if (int64_t{a.width} * a.supersample > kMaxImageSide)
      throw CLI::ValidationError("--width x --supersample", "expected at most " + std::to_string(kMaxImageSide) +
                                                                 " rays across, got " + std::to_string(int64_t{a.width} * a.supersample));
    action = [&global] { runEval(global, a); };
  });
}

const bool registered = registerCommand({"eval", addEvalCommand});

}  // namespace
}  // namespace smokesvd::cli
