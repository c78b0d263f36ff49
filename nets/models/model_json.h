// The architectures' configurations as JSON (the "model" section of a network's config.json; every key
// is listed in docs/models.md). Reading is strict: an unknown key, a missing one or a value of the wrong
// type is an Error naming `where` (the file and section) and the key.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "nets/models/ddpm_unet.h"
#include "nets/models/unet3plus.h"

namespace smokesvd::models {

UNet3PlusConfig unet3PlusFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json toJson(const UNet3PlusConfig& config);

DdpmUNetConfig ddpmUNetFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json toJson(const DdpmUNetConfig& config);

// Throws Error naming `where` and the first key of `json` (an object) that is not in `known`.
void requireKnownKeys(const nlohmann::json& json, const std::vector<std::string>& known, const std::string& where);

}  // namespace smokesvd::models
