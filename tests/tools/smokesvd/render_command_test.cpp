#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "pipeline/media/image.h"
#include "pipeline/media/video.h"
#include "tests/harness/command.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class RenderCommandTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (directory_ / name).string(); }
  io::TemporaryFolder directory_{"render-cli"};
};

TEST_F(RenderCommandTest, RendersScalarFlowStyleNpzToPngs) {
  // ScalarFlow stores density as 'data' [z, y, x, 1].
  io::writeNpz(path("density_000.npz"), {{"data", io::NpyArray::fromFloats({5, 9, 7, 1}, randomValues(315, 1, 0, 1))}});
  const CommandResult result =
      runSmokesvd("render " + path("density_000.npz") + " --angles 0,90 --width 7 --height 9 --bits 16 --light 0,1,0 "
                  "--out " + path("out"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  for (const char* name : {"density_000_a000.0.png", "density_000_a090.0.png"}) {
    const media::Image image = media::readPng(path("out") + "/" + name);
    EXPECT_EQ(image.width, 7);
    EXPECT_EQ(image.height, 9);
    float maximum = 0;
    for (float v : image.values) maximum = std::max(maximum, v);
    EXPECT_GT(maximum, 0.1f) << name;
  }
}

TEST_F(RenderCommandTest, TurntableWritesAVideoWhenFfmpegIsThere) {
  if (!media::findFfmpeg()) GTEST_SKIP() << "ffmpeg not installed";
  io::writeNpy(path("d.npy"), io::NpyArray::fromFloats({6, 8, 6}, randomValues(288, 2, 0, 1)));
  const CommandResult result = runSmokesvd("render " + path("d.npy") + " --turntable 4 --preset tiny --mp4 --out " +
                                           path("turn"));
  ASSERT_EQ(result.exitCode, 0) << result.err;
  EXPECT_TRUE(fs::exists(path("turn") + "/d_t003.png"));
  EXPECT_EQ(media::probeVideo(path("turn") + "/d_turntable.mp4").width, 16);
}

TEST_F(RenderCommandTest, BadInputsGiveClearErrors) {
  std::ofstream(path("junk.npy")) << "junk";
  io::writeNpz(path("velocity.npz"), {{"data", io::NpyArray::fromFloats({2, 3, 4, 3}, std::vector<float>(72, 0.0f))}});
  io::writeNpz(path("two.npz"), {{"a", io::NpyArray::fromFloats({2, 3, 4}, std::vector<float>(24, 0.0f))},
                                 {"b", io::NpyArray::fromFloats({2, 3, 4}, std::vector<float>(24, 0.0f))}});
  const struct {
    std::string arguments, message;
  } cases[] = {
      {"render " + path("missing.npz") + " --out " + path("o"), "missing.npz"},
      {"render " + path("junk.npy") + " --out " + path("o"), "junk.npy"},
      {"render " + path("velocity.npz") + " --out " + path("o"), "velocity field"},
      {"render " + path("two.npz") + " --out " + path("o"), "cannot tell which array"},
      {"render " + path("two.npz") + " --key c --out " + path("o"), "no array 'c'"},
      {"render " + path("two.npz") + " --key a --angles 0,x --out " + path("o"), "--angles"},
      {"render " + path("two.npz") + " --key a --preset huge --out " + path("o"), "unknown preset"},
      {"render " + path("two.npz") + " --key a --cameras " + path("none.json") + " --out " + path("o"), "none.json"},
  };
  for (const auto& c : cases) {
    const CommandResult result = runSmokesvd(c.arguments);
    EXPECT_EQ(result.exitCode, 1) << c.arguments;
    EXPECT_NE(result.err.find(c.message), std::string::npos) << c.arguments << "\n" << result.err;
  }
}

}  // namespace
}  // namespace smokesvd::testing
