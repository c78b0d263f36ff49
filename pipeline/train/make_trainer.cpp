#include "pipeline/train/make_trainer.h"

#include "pipeline/train/grho_trainer.h"
#include "runtime/error.h"

namespace smokesvd::train {

std::unique_ptr<StageTrainer> makeTrainer(Context& context, const NetworkConfig& config,
                                          const dataset::SceneDataset& data, const std::filesystem::path&) {
  switch (config.network) {
    case Network::GrhoCoarse:
    case Network::GrhoFine:
      return std::make_unique<GrhoTrainer>(context, config, data);
    default:
      throw Error("training " + networkName(config.network) + " is not available yet");
  }
}

}  // namespace smokesvd::train
