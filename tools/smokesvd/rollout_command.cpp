// `smokesvd rollout --data DIR --models DIR`: SvDiff's autoregressive rollout on held-out scenes against
// the mirrored front view (pipeline/reconstruct/side_view_rollout.h); prints a summary, writes JSON.
#include <fstream>
#include <iostream>

#include "nets/io/file_io.h"
#include "pipeline/reconstruct/side_view_rollout.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct RolloutArguments {
  std::string data, models, out, preset = "small";
  int frames = 40, scenes = 6, ddimSteps = 20, initSteps = 50, sideViewStart = reconstruct::SideViewOptions{}.start;
  double eta = 1.0;
  uint64_t seed = 0;
  int validationEvery = 10;
};

void addRolloutCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static RolloutArguments a;
  CLI::App* c = app.add_subcommand("rollout", "SvDiff's side views over an autoregressive rollout on held-out scenes");
  c->add_option("--data", a.data, "folder of simulated scenes (their validation split is used)")->required();
  c->add_option("--models", a.models, "folder of trained networks (default: the shipped models/<preset>)");
  c->add_option("--preset", a.preset, "tiny, small (default) or paper");
  c->add_option("--frames", a.frames, "frames of the rollout (default 40)")->check(wholeNumber(1, sim::kMaxFrames));
  c->add_option("--scenes", a.scenes, "validation scenes to roll out (default 6)")->check(wholeNumber(1, 100000));
  c->add_option("--validation-every", a.validationEvery, "the dataset's split: every N-th scene is held out (default 10)")
      ->check(wholeNumber(1, 100000));
  c->add_option("--ddim-steps", a.ddimSteps, "DDIM steps per frame (default 20)")->check(wholeNumber(1, 10000));
  c->add_option("--init-steps", a.initSteps, "DDIM steps of frames 0 and 1 (default 50)")->check(wholeNumber(1, 10000));
  c->add_option("--eta", a.eta, "DDIM eta (default 1)")->check(number(0, 100));
  c->add_option("--side-view-start", a.sideViewStart,
                "DDIM start step: -1 samples from pure noise (the paper), lower from the mirrored front view noised to "
                "that step (default " + std::to_string(a.sideViewStart) + "; docs/reconstruction.md)")
      ->check(wholeNumber(-1, 100000));
  c->add_option("--seed", a.seed, "sampling seed")->check(wholeNumber(0, INT64_MAX));
  c->add_option("--out", a.out, "JSON file of the per-frame figures");
  c->callback([&global, &action] {
    action = [&global] {
      const Preset& p = preset(a.preset);
      dataset::DatasetOptions options;
      options.validationEvery = a.validationEvery;
      const dataset::SceneDataset data(a.data, p, options);
      Context context(global.contextOptions());
      reconstruct::MethodModels models(context, a.models.empty() ? reconstruct::defaultModelsFolder(a.preset) : std::filesystem::path(a.models), p);
      reconstruct::SideViewOptions side;
      side.steps = a.ddimSteps;
      side.initSteps = a.initSteps;
      side.eta = a.eta;
      side.start = a.sideViewStart;
      side.seed = a.seed;
      const reconstruct::RolloutResult r = reconstruct::sideViewRollout(context, models, data, a.frames, a.scenes, side);
      std::cout << "side views over " << a.frames << " frames of " << r.scenes << " held-out scenes: PSNR " << r.mean()
                << " dB (mirrored front view " << r.mirroredMean() << " dB); first 10 frames " << r.firstTen()
                << " dB, last 10 " << r.lastTen() << " dB\n";
      if (!a.out.empty())
        io::writeAtomically(a.out, [&](const std::filesystem::path& tmp) { std::ofstream(tmp) << r.toJson().dump(2) << "\n"; });
    };
  });
}

const bool registered = registerCommand({"rollout", addRolloutCommand});

}  // namespace
}  // namespace smokesvd::cli
