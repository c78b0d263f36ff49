#include "pipeline/train/model_weights.h"

#include <string>

#include "nets/io/safetensors.h"
#include "nets/modules/weights.h"
#include "nets/optim/checkpoint.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

// "<source> holds a <network> model[ of the <preset> preset], and ...; " where the file's metadata names
// another network or preset than `config`, else "".
std::string otherModelIn(const io::SafetensorsFile& file, const std::string& source, const networks::NetworkConfig& config) {
  const auto network = file.metadata.find("network"), preset = file.metadata.find("preset");
  if (network == file.metadata.end()) return "";
  const std::string ours = networks::networkName(config.network);
  const bool otherPreset = preset != file.metadata.end() && preset->second != config.preset;
  if (network->second == ours && !otherPreset) return "";
  return source + " holds a " + network->second + " model" +
         (preset != file.metadata.end() ? " of the " + preset->second + " preset" : std::string()) +
         ", and the config is of " + ours + " at the " + config.preset + " preset; ";
}

}  // namespace

void loadWeightsFor(const std::filesystem::path& path, modules::Module& model, const networks::NetworkConfig& config) {
  const std::string source = path.string();
  io::SafetensorsFile file = io::readSafetensors(path);
  if (optim::isCheckpoint(file)) file = optim::checkpointEmaWeights(file, source);
  try {
    modules::loadWeights(file, model, source);
  } catch (const Error& error) {
    throw Error(otherModelIn(file, source, config) + error.what());
  }
}

}  // namespace smokesvd::train
