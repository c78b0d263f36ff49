#include "pipeline/train/model_weights.h"

#include <map>
#include <string>

#include "nets/io/safetensors.h"
#include "nets/modules/weights.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

// "<path> holds a <network> model of the <preset> preset, and ...; " where the file's metadata names another
// network or preset than `config`, else "".
std::string otherModelIn(const std::filesystem::path& path, const networks::NetworkConfig& config) {
  std::map<std::string, std::string> metadata;
  try {
    metadata = io::readSafetensors(path).metadata;
  } catch (const Error&) {
    return "";  // the failed load's own message says what is wrong with the file
  }
  const auto network = metadata.find("network"), preset = metadata.find("preset");
  if (network == metadata.end() || preset == metadata.end()) return "";
  const std::string ours = networks::networkName(config.network);
  if (network->second == ours && preset->second == config.preset) return "";
  return path.string() + " holds a " + network->second + " model of the " + preset->second +
         " preset, and the config is of " + ours + " at the " + config.preset + " preset; ";
}

}  // namespace

void loadWeightsFor(const std::filesystem::path& path, modules::Module& model, const networks::NetworkConfig& config) {
  try {
    modules::loadWeights(path, model);
  } catch (const Error& error) {
    throw Error(otherModelIn(path, config) + error.what());
  }
}

}  // namespace smokesvd::train
