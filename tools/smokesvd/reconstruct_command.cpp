// `smokesvd reconstruct INPUT --out DIR`: one video of smoke in; per frame its density, velocity and
// inflow, 16 views and the side view out (docs/reconstruction.md):
//
//   smokesvd reconstruct plume.mp4 --out recon/                     shipped small-preset weights
//   smokesvd reconstruct frames/ --out recon/ --framing box --intensity none --frames 0:60
//   smokesvd reconstruct train02.mp4 --camera info.json --out recon/  calibrated real footage
//   smokesvd reconstruct plume.mp4 --out recon/ --resume             continue an interrupted run
#include <iostream>

#include "pipeline/progress.h"
#include "pipeline/reconstruct/reconstruction.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"
#include "tools/smokesvd/side_view_flags.h"

namespace smokesvd::cli {
namespace {

struct ReconstructArguments {
  std::string input, out, models, frames, camera, framing, intensity = "auto", background = "level", sideView = "synthesize", sideViews;
  std::string preset = "small";
  float threshold = 0.02f, target = 0.9f;
  reconstruct::SideViewOptions sampling;  // --seed, --ddim-steps, --init-steps, --eta, --side-view-start, --side-samples, --init-share
  int inflowIterations = 40;
  reconstruct::PolishOptions polish;  // --polish and its --polish-* weights
  double inflowLr = 0.005, inflowHeight = 0.25;
  bool noRefine = false, noProgressive = false, noVideos = false, resume = false, overwrite = false, orthographicInput = false;
};

void parseFrames(const std::string& text, reconstruct::InputOptions& in) {
  if (text.empty()) return;
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw Error("--frames: expected A:B (first frame, one past the last) or A:, got '" + text + "'");
  try {
    std::size_t used = 0;
    in.first = std::stoi(text.substr(0, colon), &used);
    if (used != colon) throw std::invalid_argument("first");
    const std::string end = text.substr(colon + 1);
    if (!end.empty()) {
      const int last = std::stoi(end, &used);
      if (used != end.size()) throw std::invalid_argument("last");
      if (last <= in.first) throw Error("--frames: B must be greater than A in A:B, got '" + text + "'");
      in.count = last - in.first;
    }
  } catch (const std::logic_error&) {
    throw Error("--frames: expected A:B with whole numbers, got '" + text + "'");
  }
  if (in.first < 0) throw Error("--frames: the first frame must be >= 0");
}

void runReconstruct(const GlobalOptions& global, const ReconstructArguments& a) {
  reconstruct::ReconstructOptions o;
  o.input.input = a.input;
  parseFrames(a.frames, o.input);
  o.input.intensity = a.intensity;
  o.input.threshold = a.threshold;
  o.input.target = a.target;
  if (a.background != "level" && a.background != "first") throw Error("--background: expected level or first");
  o.input.background = a.background == "first" ? reconstruct::Background::First : reconstruct::Background::Level;
  if (!a.camera.empty()) {
    const auto colon = a.camera.rfind(':');
    o.input.calibration = colon == std::string::npos ? a.camera : a.camera.substr(0, colon);
    if (colon != std::string::npos) o.input.camera = a.camera.substr(colon + 1);
    if (!a.framing.empty() && a.framing != "calibrated")
      throw Error("--camera crops the calibrated box; it cannot be combined with --framing " + a.framing);
    o.input.framing = reconstruct::Framing::Calibrated;
    o.input.orthographic = a.orthographicInput;
  } else if (a.orthographicInput) {
    throw Error("--orthographic-input concerns calibrated footage; it needs --camera info.json[:VIDEO]");
  } else if (!a.framing.empty()) {
    o.input.framing = reconstruct::parseFraming(a.framing);
    if (o.input.framing == reconstruct::Framing::Calibrated) throw Error("--framing calibrated needs --camera info.json[:VIDEO]");
  }
  o.out = a.out;
  o.models = a.models;
  o.preset = a.preset;
  o.resume = a.resume;
  o.overwrite = a.overwrite;
  o.videos = !a.noVideos;
  if (a.sideView != "synthesize" && a.sideView != "mirror") throw Error("--side-view: expected synthesize or mirror");
  o.sideView = a.sampling;
  o.sideView.synthesize = a.sideView == "synthesize";
  if (!a.sideViews.empty() && a.sideView == "mirror") throw Error("--side-views gives the side views; it cannot be combined with --side-view mirror");
  o.sideViews = a.sideViews;
  o.density.refine = !a.noRefine;
  o.density.progressive = !a.noProgressive;
  o.motion.inflowIterations = a.inflowIterations;
  o.motion.inflowLr = a.inflowLr;
  o.motion.inflowHeight = a.inflowHeight;
  o.polish = a.polish;
  Context context(global.contextOptions());
  const reconstruct::ReconstructResult r = reconstruct::runReconstruction(context, o);
  if (r.complete && r.framesThisCall == 0)
    std::cerr << a.out << ": already complete\n";
  else
    std::cerr << a.out << ": " << r.framesThisCall << " frames in " << formatDuration(r.seconds)
              << (r.complete ? " (complete)" : "") << "\n";
}

void addReconstructCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static ReconstructArguments a;
  CLI::App* c = app.add_subcommand("reconstruct", "reconstruct density, velocity and inflow from one video of smoke");
  c->add_option("input", a.input, "a video, a folder of PNG frames, or an .npy/.npz image stack [T, H, W]")->required();
  c->add_option("--out", a.out, "output folder")->required();
  c->add_option("--models", a.models, "folder of trained networks (default: the shipped models/<preset>)");
  c->add_option("--preset", a.preset, "small (default) or paper: sizes of the reconstruction and its networks");
  c->add_option("--frames", a.frames, "A:B, frames A to B-1 of the input (A: to the end)");
  c->add_option("--camera", a.camera, "info.json[:VIDEO]: calibrated footage; crops the calibrated box's projection");
  c->add_flag("--orthographic-input", a.orthographicInput,
              "with --camera: take the crop as the orthographic front view, neither rectified onto the box's mid-plane "
              "nor fitted through the perspective camera (a baseline)");
  c->add_option("--framing", a.framing, "box (the whole frame is the box's front view) or auto (find the smoke; default)");
  c->add_option("--intensity", a.intensity, "auto (default), none, or a gain: how input values map to the networks' units");
  c->add_option("--background", a.background, "level (default: one black level) or first (frame 0 per pixel)");
  c->add_option("--threshold", a.threshold, "noise floor after normalisation (default 0.02)")->check(number(0, 1));
  c->add_option("--target", a.target, "the level the footage's 99.9th percentile maps to (default 0.9)")->check(positiveNumber(1e6));
  c->add_option("--side-view", a.sideView,
                "synthesize (SvDiff, default) or mirror (the mirrored front view: the baseline, and with the shipped "
                "small weights the better side view on real footage; docs/evaluation.md)");
  c->add_option("--side-views", a.sideViews,
                "side views given, not synthesised (a true side view as an oracle, or a second camera at 90 degrees): "
                "a video, PNG folder or image stack, read like the input with box framing, one per frame");
  addSideViewSamplingFlags(*c, a.sampling);
  c->add_flag("--no-refine", a.noRefine, "skip the novel-view refinement (the coarse density; an ablation)");
  c->add_flag("--no-progressive", a.noProgressive, "refine every novel view in one pass (an ablation)");
  c->add_option("--inflow-iterations", a.inflowIterations, "AdamW iterations of the inflow per frame (default 40)")
      ->check(wholeNumber(0, 100000));
  c->add_option("--inflow-lr", a.inflowLr, "learning rate of the inflow optimisation (default 0.005)")->check(positiveNumber(1e3));
  c->add_option("--inflow-height", a.inflowHeight, "the inflow is zero above this fraction of the box (default 0.25)")
      ->check(number(0, 1));
  c->add_option("--polish", a.polish.steps, "N optimisation steps per frame on velocity and inflow through the renderer (default 0)")
      ->check(wholeNumber(0, 100000));
  c->add_option("--polish-lr", a.polish.lr, "learning rate of the polish (default 0.02)")->check(positiveNumber(1e3));
  c->add_option("--polish-input-weight", a.polish.inputWeight, "weight of the input view's error in the polish (default 1)")
      ->check(number(0, 1e6));
  c->add_option("--polish-view-weight", a.polish.viewWeight,
                "weight of the other views' error against the refined views, over all of them (default 0.25)")
      ->check(number(0, 1e6));
  c->add_option("--polish-divergence-weight", a.polish.divergenceWeight, "weight of the velocity's mean squared divergence (default 1)")
      ->check(number(0, 1e6));
  c->add_option("--polish-prior-weight", a.polish.priorWeight,
                "weight of the velocity's squared distance from G_u's (default 1)")
      ->check(number(0, 1e6));
  c->add_flag("--no-videos", a.noVideos, "skip input/side/orbit mp4 and the contact sheet");
  c->add_flag("--resume", a.resume, "continue the run in --out at its first unfinished frame");
  c->add_flag("--overwrite", a.overwrite, "replace the reconstruction in --out");
  c->callback([&global, &action] { action = [&global] { runReconstruct(global, a); }; });
}

const bool registered = registerCommand({"reconstruct", addReconstructCommand});

}  // namespace
}  // namespace smokesvd::cli
