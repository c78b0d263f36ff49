// The weights the project ships (models/small/): every network of the method is there, with its config
// and model card, and its weights load into the architecture its config describes (a tensor of another
// name or shape is an error naming it); so do the fine G_rho's weights for 16 true views, which the
// reconstruction does not load.
#include <gtest/gtest.h>

#include <filesystem>

#include "nets/models/model_json.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/trained_model.h"
#include "pipeline/preset.h"
#include "pipeline/reconstruct/method_models.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class ShippedModelsTest : public GpuTest {};

TEST_F(ShippedModelsTest, EverySmallNetworkLoadsIntoItsArchitecture) {
  const fs::path folder = reconstruct::defaultModelsFolder("small");
  for (const char* network : {"grho-coarse", "grho-fine", "nvref", "gu", "svdiff-init", "svdiff"})
    for (const char* file : {"config.json", "model.safetensors", "model_card.md"})
      EXPECT_TRUE(fs::is_regular_file(folder / network / file)) << (folder / network / file);
  const reconstruct::MethodModels models(context(), folder, preset("small"));
  EXPECT_EQ(models.hashes.size(), 6u);
}

TEST_F(ShippedModelsTest, TheFineDensityGeneratorForTrueViewsLoadsIntoItsArchitecture) {
  const fs::path folder = reconstruct::defaultModelsFolder("small") / "grho-fine-true-views";
  EXPECT_TRUE(fs::is_regular_file(folder / "model_card.md")) << folder;
  networks::TrainedModel trained{networks::readNetworkConfig(folder / "config.json"), folder / "model.safetensors"};
  EXPECT_EQ(trained.config.network, networks::Network::GrhoFine);
  networks::DensityGenerator generator(
      context(), models::unet3PlusFromJson(trained.config.model, trained.config.source + " [model]"), preset("small"));
  networks::loadTrainedWeights(trained, generator.net());
}

}  // namespace
}  // namespace smokesvd::testing
