#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

// Each network's inference benchmark times one forward pass and counts its FLOPs: for G_u those of the
// model card's forward (one sample, the training benchmark's forward_flops).
TEST(BenchInfer, TimesOneForwardOfEachNetwork) {
  for (const char* network : {"grho-coarse", "grho-fine", "nvref", "gu", "svdiff", "svdiff-init"}) {
    SCOPED_TRACE(network);
    const std::string name = std::string("infer/") + network + "/tiny";
    const CommandResult result = runSmokesvd("bench " + name + " --json --runs 1 --warmup 0 --no-reference");
    ASSERT_EQ(result.exitCode, 0) << result.err;
    const nlohmann::json results = nlohmann::json::parse(result.out).at("results");
    ASSERT_EQ(results.size(), 1u) << result.out;
    const nlohmann::json& r = results[0];
    EXPECT_EQ(r.at("kernel"), name);
    EXPECT_FALSE(r.contains("not_run")) << result.out;
    EXPECT_GT(r.at("median_ns").get<double>(), 0);
    EXPECT_GT(r.at("flops").get<double>(), 0);
    if (std::string(network) == "gu") {
      EXPECT_NEAR(r.at("flops").get<double>(), 0.0152e9, 0.0005e9);
    }
  }
}

}  // namespace
}  // namespace smokesvd::testing
