// A network's configuration: which network, for which preset, its architecture ("model"), how it trains
// ("train", "data") and its loss weights and options ("loss", "options", read by its trainer). The
// defaults of every preset are models/configs/<preset>/<network>.json, embedded in the binary; a
// trained model's folder holds the config it was trained with (config.json). docs/models.md lists
// every key. Reading is strict: an unknown key, a missing one or a value of the wrong type is an
// Error naming the file, the section and the key.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace smokesvd::networks {

enum class Network { GrhoCoarse, GrhoFine, NvRef, Gu, SvDiff, SvDiffInit };

std::string networkName(Network network);  // "grho-coarse", "grho-fine", "nvref", "gu", "svdiff", "svdiff-init"
// Error listing the networks if `name` is none of them.
Network parseNetwork(const std::string& name);
const std::vector<Network>& allNetworks();

struct TrainSettings {
  int64_t steps = 1000;
  double lr = 5e-4;
  int64_t warmup = 0;
  double minLrFraction = 0.1;  // cosine decay from lr to lr * this over the steps after the warm-up
  double weightDecay = 0.0;    // AdamW's decoupled decay
  double clip = 1.0;           // global gradient-norm clip
  double ema = 0.999;          // EMA decay of the weights (the EMA is what a run exports)
  int batch = 1;
  int64_t checkpointEvery = 100, validateEvery = 500, logEvery = 10;
  int validationSamples = 16;
};

struct DataSettings {
  int validationEvery = 10;  // every N-th scene is held out for validation
  bool mirror = true;        // random mirroring in x
  double densityScaleMin = 1.0, densityScaleMax = 1.0;  // random density scale (log-uniform)
};

struct NetworkConfig {
  Network network = Network::GrhoFine;
  std::string preset;
  nlohmann::json model;    // the architecture (nets/models/model_json.h)
  TrainSettings train;
  DataSettings data;
  nlohmann::json loss;     // loss weights, read by the network's trainer
  nlohmann::json options;  // network options, read by the network's trainer
  std::string source;      // the file (or "built-in small/grho-fine") errors name
};

NetworkConfig parseNetworkConfig(const nlohmann::json& json, const std::string& source);
NetworkConfig readNetworkConfig(const std::filesystem::path& path);
// The same, and an Error ("<path>: configures gu, not nvref") unless it configures `network`.
NetworkConfig readNetworkConfig(const std::filesystem::path& path, Network network);
NetworkConfig defaultNetworkConfig(const std::string& preset, Network network);
nlohmann::json toJson(const NetworkConfig& config);

// Reads a loss or options section: the value of `key` (Error naming the section if missing or not a number).
double number(const nlohmann::json& section, const std::string& key, const std::string& where);
int64_t integer(const nlohmann::json& section, const std::string& key, const std::string& where);
bool flag(const nlohmann::json& section, const std::string& key, const std::string& where);
std::string text(const nlohmann::json& section, const std::string& key, const std::string& where);

}  // namespace smokesvd::networks
