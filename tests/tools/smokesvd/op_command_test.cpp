// `smokesvd op` itself: the catalogue, forward and backward on .npy files, attributes, and one-line
// errors for bad command lines (the ops' own runs are in tests/nets/op_driver_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "tests/harness/command.h"
#include "tests/harness/op_runner.h"

namespace smokesvd::testing {
namespace {

const io::NpyArray kA = io::NpyArray::fromFloats({2, 3}, {1, 2, 3, 4, 5, 6});
const io::NpyArray kB = io::NpyArray::fromFloats({2, 3}, {-1, 0.5f, 2, 0, 1, 3});
const io::NpyArray kG = io::NpyArray::fromFloats({2, 3}, {1, 1, 1, 2, 2, 2});

TEST(OpCommand, ListsOpsWithTheirSignature) {
  const CommandResult result = runSmokesvd("op --list");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("mul: y = a * b"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("inputs: a, b"), std::string::npos);
}

TEST(OpCommand, RunsForwardAndBackwardOnNpyFiles) {
  const OpRun run = runOpCommand("mul", {{"a", kA}, {"b", kB}, {"grad_y", kG}}, {"y", "grad_a", "grad_b"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(run.outputs.at("y").floats, (std::vector<float>{-1, 1, 6, 0, 5, 18}));
  EXPECT_EQ(run.outputs.at("grad_a").floats, (std::vector<float>{-1, 0.5f, 2, 0, 2, 6}));  // g * b
  EXPECT_EQ(run.outputs.at("grad_b").floats, (std::vector<float>{1, 2, 3, 8, 10, 12}));   // g * a
}

TEST(OpCommand, AttributesAreParsedAndChecked) {
  const OpRun half = runOpCommand("scale", {{"x", kA}}, {"y"}, {"alpha=0.5"});
  ASSERT_EQ(half.exitCode, 0) << half.err;
  EXPECT_EQ(half.outputs.at("y").floats, (std::vector<float>{0.5f, 1, 1.5f, 2, 2.5f, 3}));
  const OpRun bad = runOpCommand("scale", {{"x", kA}}, {"y"}, {"alpha=abc"});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("alpha='abc' is not a number"), std::string::npos) << bad.err;
  const OpRun missing = runOpCommand("scale", {{"x", kA}}, {});
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE(missing.err.find("'alpha' is required"), std::string::npos) << missing.err;
}

TEST(OpCommand, BadInputsAreOneLineErrors) {
  const io::TemporaryFolder dir("op-command");
  io::writeNpy(dir / "a.npy", kA);
  io::writeNpy(dir / "b.npy", kB);
  for (const std::string& arguments :
       {std::string("op nosuchop"), "op mul --in a=" + dir.file("a.npy"), "op mul --in a=" + dir.file("missing.npy") + " --in b=x",
        "op mul --in a=" + dir.file("a.npy") + " --in b=" + dir.file("b.npy") + " --in c=" + dir.file("b.npy")}) {
    const CommandResult result = runSmokesvd(arguments);
    EXPECT_NE(result.exitCode, 0) << arguments;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << arguments << ": " << result.err;
  }
}

TEST(OpCommand, OversizedTensorIsAOneLineError) {
  // One float more than the device's largest tensor (128 MiB on lavapipe, 512 MiB on NVIDIA GPUs).
  const CommandResult info = runSmokesvd("info --json");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  int64_t maxBytes = 0;
  const nlohmann::json devices = nlohmann::json::parse(info.out).at("devices");
  for (const auto& device : devices)
    if (device.at("chosen").get<bool>()) maxBytes = device.at("max_tensor_bytes").get<int64_t>();
  ASSERT_GT(maxBytes, 0) << info.out;
  const int64_t elements = maxBytes / 4 + 1;
  const io::TemporaryFolder dir("op-command");
  io::writeNpy(dir / "big.npy", io::NpyArray::fromFloats({elements}, std::vector<float>(elements, 1.0f)));
  const CommandResult result =
      runSmokesvd("op scale --attr alpha=2 --in x=" + dir.file("big.npy") + " --out y=" + dir.file("y.npy"));
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find("tensor [" + std::to_string(elements) + "]"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "y.npy"));
}

}  // namespace
}  // namespace smokesvd::testing
