// `smokesvd validate NETWORK --data DIR`: a trained model measured on the held-out scenes of DIR with the
// metrics its training validates with, without training (pipeline/train/validate_model.h; docs/models.md,
// "Validating a trained model"):
//
//   smokesvd validate nvref --data data/small                       the shipped models/small/nvref
//   smokesvd validate nvref --data data/small --weights RUN/model.safetensors     a run's model, its config beside it
//   smokesvd validate nvref --data data/small --config other.json   the shipped weights under other options
//   smokesvd validate nvref --data data/small --weights RUN/checkpoint.safetensors   a run in progress (its EMA)
#include <chrono>
#include <fstream>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "nets/io/file_io.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/preset.h"
#include "pipeline/progress.h"
#include "pipeline/reconstruct/method_models.h"
#include "pipeline/train/validate_model.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

namespace fs = std::filesystem;

struct ValidateArguments {
  std::string network, data, models, weights, config, json;
  std::string preset = "small";
};

void validate(const GlobalOptions& global, const ValidateArguments& a) {
  const networks::Network network = networks::parseNetwork(a.network);
  const std::string name = networks::networkName(network);
  // The config: --config, else the config.json beside the weights (a run folder and a models folder both keep
  // it there); the weights: --weights, else the trained model's in the models folder of the config's preset.
  std::optional<networks::NetworkConfig> given;
  if (!a.config.empty()) given = networks::readNetworkConfig(a.config, network);
  const fs::path weightsModels =
      a.models.empty() ? reconstruct::defaultModelsFolder(given ? given->preset : a.preset) : fs::path(a.models);
  const fs::path weights = a.weights.empty() ? weightsModels / name / "model.safetensors" : fs::path(a.weights);
  if (!fs::exists(weights)) throw Error(weights.string() + ": no such weights (expected a model.safetensors of " + name + ")");
  const fs::path configPath = given ? fs::path(a.config) : weights.parent_path() / "config.json";
  if (!given && !fs::exists(configPath))
    throw Error(configPath.string() + ": no such config (expected the config.json the weights were trained with; or give --config)");
  const networks::NetworkConfig config = given ? *given : networks::readNetworkConfig(configPath, network);
  const fs::path models = !a.models.empty() ? fs::path(a.models) : reconstruct::defaultModelsFolder(config.preset);

  dataset::DatasetOptions dataOptions;
  dataOptions.validationEvery = config.data.validationEvery;
  const dataset::SceneDataset data(a.data, preset(config.preset), dataOptions);
  Context context(global.contextOptions());
  std::cerr << "validating " << name << " (" << config.preset << ") with " << weights.string() << " and "
            << configPath.string() << " on the " << data.validation().size() << " held-out scenes of " << a.data << "\n";
  const auto began = std::chrono::steady_clock::now();
  const std::vector<train::Metric> metrics = train::validateModel(context, config, data, models, weights);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  nlohmann::json values = nlohmann::json::object();
  for (const train::Metric& m : metrics) {
    std::cout << m.name << " " << m.value << "\n";
    values[m.name] = m.value;
  }
  std::cerr << "validated in " << formatDuration(seconds) << "\n";
  if (!a.json.empty()) {
    const nlohmann::json report{{"network", name},          {"preset", config.preset},
                                {"weights", weights.string()}, {"config", configPath.string()},
                                {"data", a.data},           {"held_out_scenes", data.validation().size()},
                                {"metrics", values},        {"seconds", seconds}};
    io::writeAtomically(a.json, [&](const fs::path& tmp) { std::ofstream(tmp) << report.dump(2) << "\n"; });
  }
}

void addValidateCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static ValidateArguments args;
  CLI::App* command = app.add_subcommand(
      "validate", "measure a trained network on held-out scenes with the metrics its training validates with");
  command->add_option("network", args.network, "grho-coarse, grho-fine, nvref, gu, svdiff or svdiff-init")->required();
  command->add_option("--data", args.data, "folder of scenes from `smokesvd simulate` (its held-out split is used)")->required();
  command->add_option("--models", args.models,
                      "folder of trained networks: the one measured (unless --weights) and those its trainer runs "
                      "(default: the shipped models/<preset>)");
  command->add_option("--weights", args.weights, "the model.safetensors to measure, or a run's checkpoint.safetensors (its EMA weights; default: MODELS/NETWORK/model.safetensors)");
  CLI::Option* config =
      command->add_option("--config", args.config, "config JSON, which names its preset (default: the config.json beside the weights)");
  command->add_option("--preset", args.preset, "tiny, small (default) or paper: which shipped models by default")
      ->excludes(config);
  command->add_option("--json", args.json, "also write the metrics to this JSON file");
  command->callback([&global, &action] { action = [&global] { validate(global, args); }; });
}

const bool registered = registerCommand({"validate", addValidateCommand});

}  // namespace
}  // namespace smokesvd::cli
