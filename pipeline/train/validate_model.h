// A trained model measured on its data's held-out scenes with its trainer's validation, the metrics
// `smokesvd train` writes to validation.csv every validate_every steps, without training: what
// `smokesvd validate` runs (docs/models.md, "Validating a trained model"). The config decides the trainer's
// options (e.g. NvRef's history and side views, G_rho's view sets), the number of validation samples and the
// split of the data; its weights are the model's own (a run's model.safetensors holds its EMA weights, the
// ones its last validation measured).
#pragma once

#include <filesystem>
#include <vector>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"
#include "runtime/context.h"

namespace smokesvd::train {

// `models`: the folder of trained networks the trainer loads the ones it runs from (make_trainer.h).
std::vector<Metric> validateModel(Context& context, const networks::NetworkConfig& config,
                                  const dataset::SceneDataset& data, const std::filesystem::path& models,
                                  const std::filesystem::path& weights);

}  // namespace smokesvd::train
