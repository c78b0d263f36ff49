#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

TEST(Cli, InfoListsTheChosenDevice) {
  const CommandResult result = runSmokesvd("info");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("* 0: "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("storage buffer range"), std::string::npos);
}

TEST(Cli, InfoJsonIsValid) {
  const CommandResult result = runSmokesvd("info --json");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  ASSERT_FALSE(json.at("devices").empty());
  EXPECT_TRUE(json["devices"][0].contains("max_storage_buffer_range"));
}

TEST(Cli, BadDeviceIsAOneLineError) {
  const CommandResult result = runSmokesvd("--device no-such-gpu info");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("'no-such-gpu'"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("available:"), std::string::npos) << result.err;
}

TEST(Cli, BadDeviceFromEnvironmentIsAOneLineError) {
  const CommandResult result = runSmokesvd("info", "SMOKESVD_DEVICE=42");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("'42'"), std::string::npos) << result.err;
}

TEST(Cli, MissingVulkanDriverIsAOneLineError) {
  const CommandResult result =
      runSmokesvd("info", "VK_DRIVER_FILES=/nonexistent/icd.json VK_ICD_FILENAMES=/nonexistent/icd.json");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_NE(result.err.find("smokesvd: error:"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("driver"), std::string::npos) << result.err;
}

TEST(Cli, BenchJsonReportsDeviceAndKernels) {
  const CommandResult result = runSmokesvd("bench dispatch --json --runs 2 --warmup 1");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  EXPECT_FALSE(json.at("device").get<std::string>().empty());
  ASSERT_FALSE(json.at("results").empty());
  EXPECT_GT(json["results"][0].at("median_ns").get<double>(), 0);
  EXPECT_GT(json.at("reference").at("peak_gflop_per_s").get<double>(), 0);
  EXPECT_GT(json.at("reference").at("copy_gb_per_s").get<double>(), 0);
}

// --profile-dispatches lists each recording's slowest dispatches, slowest first, with their grids and push
// constants (it implies --profile).
TEST(Cli, BenchListsTheSlowestDispatches) {
  const CommandResult result =
      runSmokesvd("bench basic/concat --json --runs 1 --warmup 0 --no-reference --profile-dispatches 1");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  const auto json = nlohmann::json::parse(result.out);
  ASSERT_FALSE(json.at("results").empty());
  const auto& entry = json["results"][0];  // concatenating two tensors: two dispatches
  ASSERT_EQ(entry.at("profile").size(), 1u);
  EXPECT_EQ(entry["profile"][0].at("dispatches").get<int>(), 2);
  const auto& slowest = entry.at("slowest_dispatches");
  ASSERT_EQ(slowest.size(), 1u);
  for (std::size_t i = 0; i < slowest.size(); ++i) {
    EXPECT_FALSE(slowest[i].at("shader").get<std::string>().empty());
    EXPECT_EQ(slowest[i].at("detail").get<std::string>().rfind("groups ", 0), 0u) << slowest[i].dump();
    if (i > 0) {
      EXPECT_GE(slowest[i - 1].at("ns").get<double>(), slowest[i].at("ns").get<double>());
    }
  }
}

TEST(Cli, BenchWithUnknownFilterFails) {
  const CommandResult result = runSmokesvd("bench no-such-kernel");
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
}

// With validation on, whatever the layer reports fails the command, even when it came while the context
// was created or destroyed. The best-practices checks (forced on here) always have something to say.
TEST(Cli, ValidationMessagesFailTheCommand) {
  const CommandResult result =
      runSmokesvd("--validation info", "VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT");
  EXPECT_EQ(result.exitCode, 1);
  EXPECT_EQ(countLines(result.err), 1) << result.err;
  EXPECT_EQ(result.err.rfind("smokesvd: error: the Vulkan validation layer reported ", 0), 0u) << result.err;
  EXPECT_NE(result.err.find("BestPractices"), std::string::npos) << result.err;
  EXPECT_EQ(runSmokesvd("--validation info").exitCode, 0) << "and without them, nothing to report";
}

TEST(Cli, UnknownSubcommandFails) {
  const CommandResult result = runSmokesvd("frobnicate");
  EXPECT_NE(result.exitCode, 0);
}

}  // namespace
}  // namespace smokesvd::testing
