#include "pipeline/train/validate_model.h"

#include "pipeline/train/make_trainer.h"
#include "pipeline/train/model_weights.h"

namespace smokesvd::train {

std::vector<Metric> validateModel(Context& context, const networks::NetworkConfig& config,
                                  const dataset::SceneDataset& data, const std::filesystem::path& models,
                                  const std::filesystem::path& weights) {
  const std::unique_ptr<StageTrainer> trainer = makeTrainer(context, config, data, models);
  loadWeightsFor(weights, trainer->model(), config);
  return trainer->validate();
}

}  // namespace smokesvd::train
