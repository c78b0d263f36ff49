#include "nets/models/model_json.h"

#include <algorithm>

#include "runtime/error.h"

namespace smokesvd::models {
namespace {

using nlohmann::json;

const json& field(const json& object, const std::string& key, const std::string& where) {
  if (!object.contains(key)) throw Error(where + ": missing key '" + key + "'");
  return object.at(key);
}

int64_t integer(const json& object, const std::string& key, const std::string& where) {
  const json& value = field(object, key, where);
  if (!value.is_number_integer()) throw Error(where + ": '" + key + "' must be an integer, got " + value.dump());
  return value.get<int64_t>();
}

double number(const json& object, const std::string& key, const std::string& where) {
  const json& value = field(object, key, where);
  if (!value.is_number()) throw Error(where + ": '" + key + "' must be a number, got " + value.dump());
  return value.get<double>();
}

std::vector<int64_t> integers(const json& object, const std::string& key, const std::string& where) {
  const json& value = field(object, key, where);
  if (!value.is_array()) throw Error(where + ": '" + key + "' must be a list of integers, got " + value.dump());
  std::vector<int64_t> out;
  for (const json& item : value) {
    if (!item.is_number_integer()) throw Error(where + ": '" + key + "' must be a list of integers, got " + value.dump());
    out.push_back(item.get<int64_t>());
  }
  return out;
}

template <typename Config>
Config validated(Config config, const std::string& where) {
  try {
    config.validate();
  } catch (const Error& error) {
    throw Error(where + ": " + error.what());
  }
  return config;
}

}  // namespace

void requireKnownKeys(const json& object, const std::vector<std::string>& known, const std::string& where) {
  if (!object.is_object()) throw Error(where + ": expected a JSON object, got " + object.dump());
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string list;
      for (const std::string& k : known) {
        if (!list.empty()) list += ", ";
        list += k;
      }
      throw Error(where + ": unknown key '" + key + "' (known: " + list + ")");
    }
}

UNet3PlusConfig unet3PlusFromJson(const json& j, const std::string& where) {
  requireKnownKeys(j, {"architecture", "dims", "in_channels", "out_channels", "filters", "cat_channels", "min_mid",
                       "negative_slope", "output", "presence_slots"},
                   where);
  if (j.value("architecture", std::string("unet3plus")) != "unet3plus")
    throw Error(where + ": 'architecture' must be \"unet3plus\"");
  UNet3PlusConfig c;
  c.dims = static_cast<int>(integer(j, "dims", where));
  c.inChannels = integer(j, "in_channels", where);
  c.outChannels = integer(j, "out_channels", where);
  c.filters = integers(j, "filters", where);
  c.catChannels = integer(j, "cat_channels", where);
  c.minMid = integer(j, "min_mid", where);
  c.negativeSlope = static_cast<float>(number(j, "negative_slope", where));
  const std::string output = field(j, "output", where).get<std::string>();
  if (output != "none" && output != "relu") throw Error(where + ": 'output' must be \"none\" or \"relu\", got \"" + output + "\"");
  c.output = output == "relu" ? OutputActivation::ReLU : OutputActivation::None;
  c.presenceSlots = j.contains("presence_slots") ? integer(j, "presence_slots", where) : 0;
  return validated(c, where);
}

json toJson(const UNet3PlusConfig& c) {
  return {{"architecture", "unet3plus"}, {"dims", c.dims}, {"in_channels", c.inChannels},
          {"out_channels", c.outChannels}, {"filters", c.filters}, {"cat_channels", c.catChannels},
          {"min_mid", c.minMid}, {"negative_slope", c.negativeSlope},
          {"output", c.output == OutputActivation::ReLU ? "relu" : "none"}, {"presence_slots", c.presenceSlots}};
}

DdpmUNetConfig ddpmUNetFromJson(const json& j, const std::string& where) {
  requireKnownKeys(j, {"architecture", "in_channels", "out_channels", "channels", "channel_mult", "res_blocks",
                       "groups", "dropout"},
                   where);
  if (j.value("architecture", std::string("ddpm_unet")) != "ddpm_unet")
    throw Error(where + ": 'architecture' must be \"ddpm_unet\"");
  DdpmUNetConfig c;
  c.inChannels = integer(j, "in_channels", where);
  c.outChannels = integer(j, "out_channels", where);
  c.channels = integer(j, "channels", where);
  c.channelMult = integers(j, "channel_mult", where);
  c.resBlocks = static_cast<int>(integer(j, "res_blocks", where));
  c.groups = static_cast<int>(integer(j, "groups", where));
  c.dropout = j.contains("dropout") ? static_cast<float>(number(j, "dropout", where)) : 0.0f;
  return validated(c, where);
}

json toJson(const DdpmUNetConfig& c) {
  return {{"architecture", "ddpm_unet"}, {"in_channels", c.inChannels}, {"out_channels", c.outChannels},
          {"channels", c.channels}, {"channel_mult", c.channelMult}, {"res_blocks", c.resBlocks},
          {"groups", c.groups}, {"dropout", c.dropout}};
}

}  // namespace smokesvd::models
