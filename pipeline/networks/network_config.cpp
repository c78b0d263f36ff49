#include "pipeline/networks/network_config.h"

#include <fstream>
#include <map>

#include "nets/models/model_json.h"
#include "pipeline/preset.h"
#include "pipeline/networks/embedded_configs.h"
#include "runtime/error.h"

namespace smokesvd::networks {
namespace {

using nlohmann::json;

const json& member(const json& section, const std::string& key, const std::string& where) {
  if (!section.is_object() || !section.contains(key)) throw Error(where + ": missing key '" + key + "'");
  return section.at(key);
}

TrainSettings parseTrain(const json& j, const std::string& where) {
  models::requireKnownKeys(j, {"steps", "lr", "warmup", "min_lr_fraction", "weight_decay", "clip", "ema", "batch",
                               "checkpoint_every", "validate_every", "log_every", "validation_samples"},
                           where);
  TrainSettings t;
  t.steps = integer(j, "steps", where);
  t.lr = number(j, "lr", where);
  t.warmup = integer(j, "warmup", where);
  t.minLrFraction = number(j, "min_lr_fraction", where);
  t.weightDecay = number(j, "weight_decay", where);
  t.clip = number(j, "clip", where);
  t.ema = number(j, "ema", where);
  t.batch = static_cast<int>(integer(j, "batch", where));
  t.checkpointEvery = integer(j, "checkpoint_every", where);
  t.validateEvery = integer(j, "validate_every", where);
  t.logEvery = integer(j, "log_every", where);
  t.validationSamples = static_cast<int>(integer(j, "validation_samples", where));
  auto positive = [&](int64_t value, const char* key) {
    if (value <= 0) throw Error(where + ": '" + key + "' must be positive, got " + std::to_string(value));
  };
  positive(t.steps, "steps");
  positive(t.batch, "batch");
  positive(t.checkpointEvery, "checkpoint_every");
  positive(t.validateEvery, "validate_every");
  positive(t.logEvery, "log_every");
  positive(t.validationSamples, "validation_samples");
  if (t.warmup < 0 || t.warmup >= t.steps) throw Error(where + ": 'warmup' must be in [0, steps)");
  if (!(t.lr > 0)) throw Error(where + ": 'lr' must be positive");
  if (!(t.minLrFraction >= 0 && t.minLrFraction <= 1)) throw Error(where + ": 'min_lr_fraction' must be in [0, 1]");
  if (!(t.weightDecay >= 0)) throw Error(where + ": 'weight_decay' must be >= 0");
  if (!(t.clip > 0)) throw Error(where + ": 'clip' must be positive");
  if (!(t.ema >= 0 && t.ema < 1)) throw Error(where + ": 'ema' must be in [0, 1)");
  return t;
}

DataSettings parseData(const json& j, const std::string& where) {
  models::requireKnownKeys(j, {"validation_every", "mirror", "density_scale"}, where);
  DataSettings d;
  d.validationEvery = static_cast<int>(integer(j, "validation_every", where));
  d.mirror = flag(j, "mirror", where);
  const json& scale = member(j, "density_scale", where);
  if (!scale.is_array() || scale.size() != 2 || !scale[0].is_number() || !scale[1].is_number())
    throw Error(where + ": 'density_scale' must be [min, max], got " + scale.dump());
  d.densityScaleMin = scale[0].get<double>();
  d.densityScaleMax = scale[1].get<double>();
  if (!(d.densityScaleMin > 0 && d.densityScaleMin <= d.densityScaleMax))
    throw Error(where + ": 'density_scale' must be [min, max] with 0 < min <= max");
  if (d.validationEvery < 2) throw Error(where + ": 'validation_every' must be at least 2");
  return d;
}

}  // namespace

std::string networkName(Network network) {
  switch (network) {
    case Network::GrhoCoarse: return "grho-coarse";
    case Network::GrhoFine: return "grho-fine";
    case Network::NvRef: return "nvref";
    case Network::Gu: return "gu";
    case Network::SvDiff: return "svdiff";
    case Network::SvDiffInit: return "svdiff-init";
  }
  return "?";
}

const std::vector<Network>& allNetworks() {
  static const std::vector<Network> all{Network::GrhoCoarse, Network::GrhoFine, Network::NvRef,
                                        Network::Gu, Network::SvDiff, Network::SvDiffInit};
  return all;
}

Network parseNetwork(const std::string& name) {
  for (const Network n : allNetworks())
    if (networkName(n) == name) return n;
  const std::string expected = "expected one of: grho-coarse, grho-fine, nvref, gu, svdiff, svdiff-init";
  if (name == "grho")
    throw Error("network 'grho' is trained as two models of one architecture: grho-coarse (the front and side views, "
                "and larger view sets that hold them) and grho-fine (all 16 views); " + expected);
  throw Error("unknown network '" + name + "'; " + expected);
}

double number(const json& section, const std::string& key, const std::string& where) {
  const json& value = member(section, key, where);
  if (!value.is_number()) throw Error(where + ": '" + key + "' must be a number, got " + value.dump());
  return value.get<double>();
}

int64_t integer(const json& section, const std::string& key, const std::string& where) {
  const json& value = member(section, key, where);
  if (!value.is_number_integer()) throw Error(where + ": '" + key + "' must be an integer, got " + value.dump());
  return value.get<int64_t>();
}

bool flag(const json& section, const std::string& key, const std::string& where) {
  const json& value = member(section, key, where);
  if (!value.is_boolean()) throw Error(where + ": '" + key + "' must be true or false, got " + value.dump());
  return value.get<bool>();
}

std::string text(const json& section, const std::string& key, const std::string& where) {
  const json& value = member(section, key, where);
  if (!value.is_string()) throw Error(where + ": '" + key + "' must be a string, got " + value.dump());
  return value.get<std::string>();
}

NetworkConfig parseNetworkConfig(const json& j, const std::string& source) {
  models::requireKnownKeys(j, {"network", "preset", "model", "train", "data", "loss", "options"}, source);
  NetworkConfig c;
  c.source = source;
  c.network = parseNetwork(text(j, "network", source));
  c.preset = text(j, "preset", source);
  preset(c.preset);  // must be a known preset
  c.model = member(j, "model", source);
  if (!c.model.is_object()) throw Error(source + ": 'model' must be an object");
  c.train = parseTrain(member(j, "train", source), source + " [train]");
  c.data = parseData(member(j, "data", source), source + " [data]");
  c.loss = member(j, "loss", source);
  c.options = member(j, "options", source);
  if (!c.loss.is_object() || !c.options.is_object()) throw Error(source + ": 'loss' and 'options' must be objects");
  return c;
}

NetworkConfig readNetworkConfig(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path)) throw Error(path.string() + ": is a folder, expected a config .json file");
  std::ifstream file(path);
  if (!file) throw Error(path.string() + ": cannot open the config file");
  json j;
  try {
    j = json::parse(file);
  } catch (const json::exception& error) {
    throw Error(path.string() + ": not valid JSON (" + error.what() + ")");
  }
  return parseNetworkConfig(j, path.string());
}

NetworkConfig readNetworkConfig(const std::filesystem::path& path, Network network) {
  NetworkConfig config = readNetworkConfig(path);
  if (config.network != network)
    throw Error(path.string() + ": configures " + networkName(config.network) + ", not " + networkName(network));
  return config;
}

NetworkConfig defaultNetworkConfig(const std::string& presetName, Network network) {
  preset(presetName);
  const std::string key = presetName + "/" + networkName(network);
  const auto& table = embeddedConfigs();
  const auto found = table.find(key);
  if (found == table.end()) throw Error("no built-in config " + key + " (models/configs/" + key + ".json)");
  return parseNetworkConfig(json::parse(found->second), "built-in " + key);
}

json toJson(const NetworkConfig& c) {
  const TrainSettings& t = c.train;
  return {{"network", networkName(c.network)},
          {"preset", c.preset},
          {"model", c.model},
          {"train",
           {{"steps", t.steps}, {"lr", t.lr}, {"warmup", t.warmup}, {"min_lr_fraction", t.minLrFraction},
            {"weight_decay", t.weightDecay}, {"clip", t.clip}, {"ema", t.ema}, {"batch", t.batch},
            {"checkpoint_every", t.checkpointEvery}, {"validate_every", t.validateEvery}, {"log_every", t.logEvery},
            {"validation_samples", t.validationSamples}}},
          {"data",
           {{"validation_every", c.data.validationEvery}, {"mirror", c.data.mirror},
            {"density_scale", {c.data.densityScaleMin, c.data.densityScaleMax}}}},
          {"loss", c.loss},
          {"options", c.options}};
}

}  // namespace smokesvd::networks
