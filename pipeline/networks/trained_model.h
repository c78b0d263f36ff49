// A trained network as `smokesvd train` leaves it: a folder <models>/<network>/ with config.json (the
// network config it was trained with) and model.safetensors (its EMA weights, PyTorch names).
#pragma once

#include <filesystem>

#include "nets/modules/module.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/preset.h"

namespace smokesvd::networks {

struct TrainedModel {
  NetworkConfig config;
  std::filesystem::path weights;
};

// <models>/<network>/. Errors name the folder and what is missing or of another preset.
TrainedModel findTrainedModel(const std::filesystem::path& models, Network network, const Preset& preset);

// Loads the weights into `module` (strict: every tensor, with its shape; the error lists the differences).
void loadTrainedWeights(const TrainedModel& model, modules::Module& module);

// No parameter of `module` needs a gradient any more: a frozen network that gradients pass through to
// its inputs (SvDiff's guidance through G_rho and G_u), or that only infers. Its parameters become constant
// (Tensor::markConstant): only the host may write them again, and what the convolutions derive from them
// (packed weights) is made once and kept for every later recording.
void freeze(modules::Module& module);

}  // namespace smokesvd::networks
