#include "pipeline/networks/trained_model.h"

#include "nets/modules/weights.h"
#include "runtime/error.h"

namespace smokesvd::networks {

TrainedModel findTrainedModel(const std::filesystem::path& models, Network network, const Preset& preset) {
  const std::filesystem::path folder = models / networkName(network);
  TrainedModel model;
  model.weights = folder / "model.safetensors";
  if (!std::filesystem::exists(folder / "config.json") || !std::filesystem::exists(model.weights))
    throw Error(folder.string() + ": no trained " + networkName(network) +
                " (expected config.json and model.safetensors; train it with `smokesvd train " + networkName(network) +
                " --out " + folder.string() + "`)");
  model.config = readNetworkConfig(folder / "config.json", network);
  if (model.config.preset != preset.name)
    throw Error((folder / "config.json").string() + ": trained for preset '" + model.config.preset + "', not '" +
                preset.name + "'");
  return model;
}

void loadTrainedWeights(const TrainedModel& model, modules::Module& module) { modules::loadWeights(model.weights, module); }

void freeze(modules::Module& module) {
  for (const auto& [name, parameter] : module.namedParameters()) {
    parameter->requiresGrad = false;
    parameter->value.markConstant();
  }
}

}  // namespace smokesvd::networks
