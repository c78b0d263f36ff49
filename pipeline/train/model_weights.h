// Weights made for a network config into its model, for `smokesvd train --init` and `smokesvd validate`: a
// model.safetensors, or a training checkpoint, which stands for the model its run would write at that step
// (its EMA weights). Strict, as modules::loadWeights; where they do not fit, the error says first whose
// weights the file says it holds (the "network" and "preset" of its metadata, as smokesvd writes them), when
// that is not the config's network and preset.
#pragma once

#include <filesystem>

#include "nets/modules/module.h"
#include "pipeline/networks/network_config.h"

namespace smokesvd::train {

void loadWeightsFor(const std::filesystem::path& path, modules::Module& model, const networks::NetworkConfig& config);

}  // namespace smokesvd::train
