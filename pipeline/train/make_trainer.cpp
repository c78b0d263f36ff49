#include "pipeline/train/make_trainer.h"

#include "pipeline/train/grho_trainer.h"
#include "pipeline/train/gu_trainer.h"
#include "pipeline/train/nvref_trainer.h"
#include "pipeline/train/svdiff_trainer.h"
#include "runtime/error.h"

namespace smokesvd::train {

std::unique_ptr<StageTrainer> makeTrainer(Context& context, const networks::NetworkConfig& config,
                                          const dataset::SceneDataset& data, const std::filesystem::path& models) {
  switch (config.network) {
    case networks::Network::GrhoCoarse:
    case networks::Network::GrhoFine:
      return std::make_unique<GrhoTrainer>(context, config, data, models);
    case networks::Network::NvRef:
      return std::make_unique<NvRefTrainer>(context, config, data, models);
    case networks::Network::Gu:
      return std::make_unique<GuTrainer>(context, config, data, models);
    case networks::Network::SvDiff:
      return std::make_unique<SvDiffTrainer>(context, config, data, models, false);
    case networks::Network::SvDiffInit:
      return std::make_unique<SvDiffTrainer>(context, config, data, models, true);
  }
  throw Error("no trainer for network " + networks::networkName(config.network));
}

}  // namespace smokesvd::train
