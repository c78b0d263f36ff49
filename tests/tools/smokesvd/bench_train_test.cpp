#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

// The training-step benchmarks report their memory, and buffer reuse lowers it.
TEST(BenchTrain, ReportsTheMemoryOfTheRecordedStepWithAndWithoutReuse) {
  const CommandResult result = runSmokesvd("bench train/conv3d-stack --json --runs 1 --warmup 0 --no-reference");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json results = nlohmann::json::parse(result.out).at("results");
  ASSERT_EQ(results.size(), 2u) << result.out;
  const nlohmann::json& reused = results[0];
  const nlohmann::json& plain = results[1];
  EXPECT_EQ(reused.at("kernel"), "train/conv3d-stack");
  EXPECT_EQ(plain.at("kernel"), "train/conv3d-stack-no-reuse");
  EXPECT_EQ(plain.at("held_bytes"), plain.at("held_bytes_without_reuse"));
  EXPECT_EQ(reused.at("held_bytes_without_reuse"), plain.at("held_bytes"));
  EXPECT_LT(reused.at("held_bytes").get<double>(), 0.5 * plain.at("held_bytes").get<double>());
  EXPECT_LT(reused.at("pool_peak_bytes").get<double>(), 0.5 * plain.at("pool_peak_bytes").get<double>());
}

}  // namespace
}  // namespace smokesvd::testing
