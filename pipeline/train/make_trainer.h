// The trainer of a network: G_rho (coarse, fine), NvRef, G_u, SvDiff and SvDiff-init. Trainers of
// networks that use others while training (NvRef renders coarse G_rho densities, SvDiff's guidance runs
// G_rho and G_u, G_u's fine-tuning runs the fine G_rho) load them from `models`, a folder holding
// <network>/model.safetensors and config.json (docs/models.md).
#pragma once

#include <filesystem>
#include <memory>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

std::unique_ptr<StageTrainer> makeTrainer(Context& context, const networks::NetworkConfig& config,
                                          const dataset::SceneDataset& data, const std::filesystem::path& models);

}  // namespace smokesvd::train
