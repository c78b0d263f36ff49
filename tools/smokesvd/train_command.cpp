// `smokesvd train NETWORK`: trains one network of the method on scenes from `smokesvd simulate`
// (docs/models.md):
//
//   smokesvd simulate --scenes 120 --seed 1000 --preset small --out data/
//   smokesvd train grho-fine --data data/ --preset small --out models/small/grho-fine
//   smokesvd train nvref --data data/ --preset small --models models/small --out models/small/nvref
//   smokesvd train grho-fine ... --resume        continue an interrupted run from its checkpoint
// Ctrl-C stops a run at its next log step with a checkpoint written there (a second Ctrl-C at once).
#include <iostream>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/preset.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/progress.h"
#include "pipeline/stop_on_signal.h"
#include "pipeline/train/training_run.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct TrainArguments {
  std::string network, data, out, config, models, init;
  std::string preset = "small";
  int64_t steps = 0;
  uint64_t seed = 0;
  bool resume = false, overwrite = false;
};

void train(const GlobalOptions& global, const TrainArguments& args) {
  const networks::Network network = networks::parseNetwork(args.network);
  networks::NetworkConfig config = args.config.empty() ? networks::defaultNetworkConfig(args.preset, network)
                                                      : networks::readNetworkConfig(args.config, network);
  if (args.steps > 0) config.train.steps = args.steps;
  if (config.train.warmup >= config.train.steps) config.train.warmup = config.train.steps / 10;

  const Preset& p = preset(config.preset);
  dataset::DatasetOptions dataOptions;
  dataOptions.validationEvery = config.data.validationEvery;
  const dataset::SceneDataset data(args.data, p, dataOptions);
  Context context(global.contextOptions());
  const std::filesystem::path models = args.models.empty() ? std::filesystem::path(args.out).parent_path() : std::filesystem::path(args.models);
  const std::unique_ptr<train::StageTrainer> trainer = train::makeTrainer(context, config, data, models);

  train::TrainingOptions options;
  options.out = args.out;
  options.resume = args.resume;
  options.overwrite = args.overwrite;
  options.seed = args.seed;
  options.initWeights = args.init;
  std::cerr << "training " << args.network << " (" << config.preset << "): " << trainer->model().parameterCount()
            << " parameters, " << trainer->forwardFlops() * 1e-9 << " GFLOP per forward; " << trainer->dataSummary() << "\n";
  const StopOnSignal stop;
  options.stop = &stop.requested();
  const train::TrainingResult result = train::runTraining(context, *trainer, config, options);
  if (result.stopped)
    std::cerr << args.out << ": stopped at step " << result.steps << " of " << config.train.steps
              << " with a checkpoint there; the same command with --resume continues it\n";
  else if (result.complete && result.stepsThisCall == 0)
    std::cerr << args.out << ": already complete (" << result.steps << " steps)\n";
  else
    std::cerr << args.out << ": " << result.steps << " steps in " << formatDuration(result.seconds)
              << (result.complete ? ", model.safetensors written" : "") << "\n";
  stop.endAsSignalled();  // interrupted, even where the run completed before its next log step
}

void addTrainCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static TrainArguments args;
  CLI::App* command = app.add_subcommand("train", "train a network of the method on simulated scenes");
  command->add_option("network", args.network, "grho-coarse, grho-fine, nvref, gu, svdiff or svdiff-init")->required();
  command->add_option("--data", args.data, "folder of scenes from `smokesvd simulate --scenes N`")->required();
  command->add_option("--out", args.out, "output folder of the run")->required();
  CLI::Option* preset = command->add_option("--preset", args.preset, "tiny, small or paper (default small): the built-in config");
  command->add_option("--config", args.config, "config JSON instead of the preset's, which names its own (docs/models.md)")
      ->excludes(preset);
  command->add_option("--models", args.models, "folder of trained networks this one uses (default: --out's parent)");
  command->add_option("--init", args.init, "start from these weights (a model.safetensors of the same architecture, or a checkpoint's EMA weights)");
  command->add_option("--steps", args.steps, "training steps (overrides the config)")->check(wholeNumber(1, 1000000000));
  command->add_option("--seed", args.seed, "seed of the sample draws")->check(wholeNumber(0, INT64_MAX));
  CLI::Option* resume = command->add_flag("--resume", args.resume, "continue the run in --out from its checkpoint");
  command->add_flag("--overwrite", args.overwrite, "discard the run in --out")->excludes(resume);
  command->callback([&global, &action] { action = [&global] { train(global, args); }; });
}

const bool registered = registerCommand({"train", addTrainCommand});

}  // namespace
}  // namespace smokesvd::cli
