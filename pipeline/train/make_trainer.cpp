#include "pipeline/train/make_trainer.h"

#include "pipeline/train/grho_trainer.h"
#include "pipeline/train/gu_trainer.h"
#include "runtime/error.h"

namespace smokesvd::train {

std::unique_ptr<StageTrainer> makeTrainer(Context& context, const networks::NetworkConfig& config,
                                          const dataset::SceneDataset& data, const std::filesystem::path& models) {
  switch (config.network) {
    case networks::Network::GrhoCoarse:
    case networks::Network::GrhoFine:
      return std::make_unique<GrhoTrainer>(context, config, data);
    case networks::Network::Gu:
      return std::make_unique<GuTrainer>(context, config, data, models);
    default:
      throw Error("training " + networks::networkName(config.network) + " is not available yet");
  }
}

}  // namespace smokesvd::train
