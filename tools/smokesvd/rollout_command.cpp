// `smokesvd rollout --data DIR --models DIR`: SvDiff's autoregressive rollout on held-out scenes against
// the mirrored front view (pipeline/reconstruct/side_view_rollout.h); prints a summary, writes JSON; with
// --keep-side-views, keeps the side views for training NvRef on them (also of the training split).
#include <fstream>
#include <iostream>

#include "nets/io/file_io.h"
#include "pipeline/reconstruct/side_view_rollout.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"
#include "tools/smokesvd/side_view_flags.h"

namespace smokesvd::cli {
namespace {

struct RolloutArguments {
  std::string data, models, out, preset = "small";
  int firstFrame = 0, frames = 40, scenes = 6;
  reconstruct::SideViewOptions sampling;  // --seed, --ddim-steps, --init-steps, --eta, --side-view-start, --side-samples, --init-share
  int validationEvery = 10;
  std::string history = "own", split = "validation", keepSideViews;
  bool quiet = false;
};

void addRolloutCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static RolloutArguments a;
  CLI::App* c = app.add_subcommand("rollout", "SvDiff's side views over an autoregressive rollout on held-out scenes");
  c->add_option("--data", a.data, "folder of simulated scenes (their validation split is used)")->required();
  c->add_option("--models", a.models, "folder of trained networks (default: the shipped models/<preset>)");
  c->add_option("--preset", a.preset, "tiny, small (default) or paper");
  c->add_option("--first-frame", a.firstFrame,
                "scene frame the rollout starts on (default 0, the start of the simulation; later: footage that begins "
                "with smoke in view)")
      ->check(wholeNumber(0, sim::kMaxFrames - 1));
  c->add_option("--frames", a.frames, "frames of the rollout (default 40)")->check(wholeNumber(1, sim::kMaxFrames));
  c->add_option("--scenes", a.scenes, "scenes of the split to roll out, the first ones (default 6)")->check(wholeNumber(1, 100000));
  c->add_option("--split", a.split, "validation (default): the held-out scenes; training: the training scenes, for --keep-side-views")
      ->check(CLI::IsMember({"validation", "training"}));
  c->add_option("--keep-side-views", a.keepSideViews,
                "folder to keep the side views in (rollout.json, scene_NNNN.npy), for NvRef's options.side_views; "
                "scenes already there are reused, so a stopped rollout resumes");
  c->add_option("--validation-every", a.validationEvery, "the dataset's split: every N-th scene is held out (default 10)")
      ->check(wholeNumber(1, 100000));
  addSideViewSamplingFlags(*c, a.sampling);
  c->add_option("--history", a.history,
                "own (default): each frame conditioned on the rollout's own previous side views, as a reconstruction is; "
                "truth: on the true ones (teacher forcing), to tell drift from harder frames")
      ->check(CLI::IsMember({"own", "truth"}));
  c->add_option("--out", a.out, "JSON file of the per-frame figures");
  c->add_flag("--quiet", a.quiet, "no progress line");
  c->callback([&global, &action] {
    action = [&global] {
      const Preset& p = preset(a.preset);
      dataset::DatasetOptions options;
      options.validationEvery = a.validationEvery;
      const dataset::SceneDataset data(a.data, p, options);
      Context context(global.contextOptions());
      reconstruct::MethodModels models(context, a.models.empty() ? reconstruct::defaultModelsFolder(a.preset) : std::filesystem::path(a.models), p);
      const reconstruct::RolloutResult r =
          reconstruct::sideViewRollout(context, models, data, a.firstFrame, a.frames, a.scenes, a.sampling,
                                       a.history == "truth" ? reconstruct::RolloutHistory::Truth : reconstruct::RolloutHistory::Own,
                                       !a.quiet, {a.split == "training", a.keepSideViews});
      std::cout << (r.trueHistory ? "side views from true history" : "side views") << " over " << a.frames << " frames from frame " << a.firstFrame << " of " << r.scenes
                << (a.split == "training" ? " training scenes" : " held-out scenes") << ": PSNR " << r.mean()
                << " dB (mirrored front view " << r.mirroredMean() << " dB, all-black " << r.blackMean()
                << " dB); first 10 frames " << r.firstTen() << " dB (mirrored " << r.mirroredFirstTen() << "), last 10 "
                << r.lastTen() << " dB (mirrored " << r.mirroredLastTen() << "); the previous frame's true side view, copied, "
                << r.previousMean() << " dB over frames 1 on\n";
      if (!a.out.empty())
        io::writeAtomically(a.out, [&](const std::filesystem::path& tmp) { std::ofstream(tmp) << r.toJson().dump(2) << "\n"; });
    };
  });
}

const bool registered = registerCommand({"rollout", addRolloutCommand});

}  // namespace
}  // namespace smokesvd::cli
