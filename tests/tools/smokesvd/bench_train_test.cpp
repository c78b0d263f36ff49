#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

// The training-step benchmarks report their memory, and buffer reuse lowers it. Held 0.55 and pool peak 0.63 of
// the memory without reuse since the convolutions keep their forward's padded input for the weight gradient
// (alive from the forward to the backward, and no second padded copy made: 36.9 / 42.2 of 67.5 MB; before,
// 30.1 / 37.7 of 86.5).
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
  EXPECT_LT(reused.at("held_bytes").get<double>(), 0.6 * plain.at("held_bytes").get<double>());
  EXPECT_LT(reused.at("pool_peak_bytes").get<double>(), 0.7 * plain.at("pool_peak_bytes").get<double>());
}

// A network's training-step benchmark times each variant of its trainer's step (here G_u's on true and on
// G_rho densities) with its memory, gives the trained network's forward FLOPs, and counts the whole step's: on true densities G_u's forward and
// backward (under three forwards: its first layer needs no gradient to its input), on G_rho's densities
// also the frozen fine G_rho's forward, which the shape column's share of the trained network shows.
TEST(BenchTrain, TimesEachVariantOfANetworksTrainingStep) {
  const CommandResult result = runSmokesvd("bench train/gu/tiny --json --runs 1 --warmup 0 --no-reference");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const nlohmann::json results = nlohmann::json::parse(result.out).at("results");
  ASSERT_GE(results.size(), 2u) << result.out;
  bool truth = false, grho = false;
  double truthFlops = 0, grhoFlops = 0;
  const double forward = 0.0152e9;  // G_u tiny, one forward
  for (const nlohmann::json& r : results) {
    const std::string name = r.at("kernel");
    ASSERT_EQ(name.rfind("train/gu/tiny:", 0), 0u) << result.out;
    EXPECT_FALSE(r.contains("not_run")) << result.out;
    truth = truth || name.find(":truth-") != std::string::npos;
    grho = grho || name.find(":grho-") != std::string::npos;
    EXPECT_GT(r.at("median_ns").get<double>(), 0) << name;
    EXPECT_GT(r.at("held_bytes").get<double>(), 0) << name;
    EXPECT_GE(r.at("pool_peak_bytes").get<double>(), r.at("held_bytes").get<double>()) << name;
    EXPECT_NEAR(r.at("forward_flops").get<double>(), forward, 0.0005e9) << name;  // the trained G_u's, one sample
    const double flops = r.at("flops").get<double>();
    const std::string shape = r.at("shape");
    if (name.find(":truth-") != std::string::npos) {
      truthFlops = flops;
      EXPECT_GT(flops, 2 * forward) << name;
      EXPECT_LT(flops, 3 * forward) << name;
      EXPECT_NE(shape.find("net 100%"), std::string::npos) << shape;
    } else {
      grhoFlops = flops;
      EXPECT_EQ(shape.find("net 100%"), std::string::npos) << shape;
    }
  }
  EXPECT_TRUE(truth && grho) << result.out;
  EXPECT_GT(grhoFlops, truthFlops);
}

}  // namespace
}  // namespace smokesvd::testing
