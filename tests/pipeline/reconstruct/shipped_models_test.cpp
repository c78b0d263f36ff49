// The weights the project ships (models/small/): every network of the method is there, with its config
// and model card, and its weights load into the architecture its config describes (a tensor of another
// name or shape is an error naming it).
#include <gtest/gtest.h>

#include <filesystem>

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

}  // namespace
}  // namespace smokesvd::testing
