#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "nets/io/npy.h"
#include "tests/harness/command.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class OpCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("smokesvd-op-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    io::writeNpy(dir_ / "a.npy", io::NpyArray::fromFloats({2, 3}, {1, 2, 3, 4, 5, 6}));
    io::writeNpy(dir_ / "b.npy", io::NpyArray::fromFloats({2, 3}, {-1, 0.5f, 2, 0, 1, 3}));
    io::writeNpy(dir_ / "g.npy", io::NpyArray::fromFloats({2, 3}, {1, 1, 1, 2, 2, 2}));
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(OpCommand, ListsOpsWithTheirSignature) {
  const CommandResult result = runSmokesvd("op --list");
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_NE(result.out.find("mul: y = a * b"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("inputs: a, b"), std::string::npos);
}

TEST_F(OpCommand, RunsForwardAndBackwardOnNpyFiles) {
  const CommandResult result =
      runSmokesvd("op mul --in a=" + file("a.npy") + " --in b=" + file("b.npy") + " --in grad_y=" + file("g.npy") +
                  " --out y=" + file("y.npy") + " --out grad_a=" + file("ga.npy") + " --out grad_b=" + file("gb.npy"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_EQ(io::readNpy(file("y.npy")).floats, (std::vector<float>{-1, 1, 6, 0, 5, 18}));
  EXPECT_EQ(io::readNpy(file("ga.npy")).floats, (std::vector<float>{-1, 0.5f, 2, 0, 2, 6}));   // g * b
  EXPECT_EQ(io::readNpy(file("gb.npy")).floats, (std::vector<float>{1, 2, 3, 8, 10, 12}));    // g * a
}

TEST_F(OpCommand, AttributesAreParsedAndChecked) {
  ASSERT_EQ(runSmokesvd("op scale --in x=" + file("a.npy") + " --attr alpha=0.5 --out y=" + file("y.npy")).exitCode, 0);
  EXPECT_EQ(io::readNpy(file("y.npy")).floats, (std::vector<float>{0.5f, 1, 1.5f, 2, 2.5f, 3}));
  const CommandResult bad = runSmokesvd("op scale --in x=" + file("a.npy") + " --attr alpha=abc --out y=" + file("y.npy"));
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("alpha='abc' is not a number"), std::string::npos) << bad.err;
  const CommandResult missing = runSmokesvd("op scale --in x=" + file("a.npy"));
  EXPECT_NE(missing.exitCode, 0);
  EXPECT_NE(missing.err.find("'alpha' is required"), std::string::npos) << missing.err;
}

TEST_F(OpCommand, BadInputsAreOneLineErrors) {
  for (const std::string& arguments :
       {std::string("op nosuchop"), "op mul --in a=" + file("a.npy"), "op mul --in a=" + file("missing.npy") + " --in b=x",
        "op mul --in a=" + file("a.npy") + " --in b=" + file("b.npy") + " --in c=" + file("b.npy")}) {
    const CommandResult result = runSmokesvd(arguments);
    EXPECT_NE(result.exitCode, 0) << arguments;
    EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << arguments << ": " << result.err;
  }
}

}  // namespace
}  // namespace smokesvd::testing

namespace smokesvd::testing {
namespace {

TEST_F(OpCommand, OversizedTensorIsAOneLineError) {
  // One float more than the device's largest tensor (128 MiB on lavapipe, 512 MiB on NVIDIA GPUs).
  const CommandResult info = runSmokesvd("info --json");
  ASSERT_EQ(info.exitCode, 0) << info.err;
  int64_t maxBytes = 0;
  const nlohmann::json devices = nlohmann::json::parse(info.out).at("devices");
  for (const auto& device : devices)
    if (device.at("chosen").get<bool>()) maxBytes = device.at("max_tensor_bytes").get<int64_t>();
  ASSERT_GT(maxBytes, 0) << info.out;
  const int64_t elements = maxBytes / 4 + 1;
  io::writeNpy(dir_ / "big.npy", io::NpyArray::fromFloats({elements}, std::vector<float>(elements, 1.0f)));
  const CommandResult result = runSmokesvd("op scale --attr alpha=2 --in x=" + file("big.npy") + " --out y=" + file("y.npy"));
  EXPECT_NE(result.exitCode, 0);
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find("tensor [" + std::to_string(elements) + "]"), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(dir_ / "y.npy"));
}

}  // namespace
}  // namespace smokesvd::testing
