#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "nets/io/temporary_folder.h"
#include "pipeline/media/image.h"
#include "pipeline/media/video.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

class ImageIoTest : public ::testing::Test {
 protected:
  fs::path path(const std::string& name) const { return directory_ / name; }
  void writeText(const fs::path& file, const std::string& text) const { std::ofstream(file) << text; }

  static media::Image ramp(int width, int height) {
    media::Image image = media::Image::gray(width, height);
    for (int r = 0; r < height; ++r)
      for (int c = 0; c < width; ++c) image.at(r, c) = static_cast<float>(r * width + c) / static_cast<float>(width * height - 1);
    return image;
  }

  io::TemporaryFolder directory_{"image"};
};

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The left-right mirror of the side-view baseline: every row reversed, rows kept in order.
TEST(MirroredRows, ReversesEachRowAndRefusesARaggedImage) {
  EXPECT_EQ(media::mirroredRows({1, 2, 3, 4, 5, 6}, 3), (std::vector<float>{3, 2, 1, 6, 5, 4}));
  EXPECT_EQ(media::mirroredRows({}, 2), std::vector<float>{});
  EXPECT_THROW(media::mirroredRows({1, 2, 3}, 2), Error);
}

TEST_F(ImageIoTest, PngRoundTripsAt8And16Bits) {
  const media::Image image = ramp(13, 7);
  for (int bits : {8, 16}) {
    media::writePng(path("a.png"), image, bits);
    EXPECT_FALSE(fs::exists(path("a.png.tmp")));
    const media::Image back = media::readPng(path("a.png"));
    ASSERT_EQ(back.width, 13);
    ASSERT_EQ(back.height, 7);
    const double step = bits == 8 ? 1.0 / 255 : 1.0 / 65535;
    for (std::size_t i = 0; i < image.values.size(); ++i) ASSERT_NEAR(back.values[i], image.values[i], 0.5 * step + 1e-7);
  }
}

TEST_F(ImageIoTest, RgbPngReadsAsLuminance) {
  media::Image rgb;
  rgb.width = 2;
  rgb.height = 1;
  rgb.channels = 3;
  rgb.values = {1, 0, 0, 0, 0, 1};
  media::writePng(path("rgb.png"), rgb);
  const media::Image gray = media::readPng(path("rgb.png"));
  EXPECT_NEAR(gray.values[0], 0.299, 0.003);
  EXPECT_NEAR(gray.values[1], 0.114, 0.003);
}

TEST_F(ImageIoTest, BadPngFilesGiveErrorsNamingThem) {
  writeText(path("broken.png"), "this is not a png");
  EXPECT_NE(errorOf([&] { media::readPng(path("broken.png")); }).find("broken.png: not a readable PNG"), std::string::npos);
  EXPECT_NE(errorOf([&] { media::readPng(path("missing.png")); }).find("missing.png: no such file"), std::string::npos);
  EXPECT_NE(errorOf([&] { media::writePng(path("no/such/folder/x.png"), ramp(3, 3)); }).find("cannot write"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { media::writePng(path("x.png"), ramp(3, 3), 12); }).find("bit depth"), std::string::npos);
}

TEST_F(ImageIoTest, PngFolderIsAFrameSequence) {
  fs::create_directories(path("frames"));
  for (int i = 0; i < 3; ++i)
    media::writePng(path("frames/f" + std::to_string(i) + ".png"), media::Image::gray(4, 3, 0.25f * static_cast<float>(i)));
  const std::vector<media::Image> frames = media::readFrames(path("frames"), 1, -1);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_NEAR(frames[1].values[0], 0.5, 0.003);
  EXPECT_NE(errorOf([&] { media::readFrames(path("nothing-here")); }).find("no such file or folder"), std::string::npos);
}

TEST_F(ImageIoTest, UnreadableVideoIsAClearError) {
  if (!media::findFfmpeg()) GTEST_SKIP() << "ffmpeg not installed";
  writeText(path("garbage.mp4"), "not a video at all");
  const std::string message = errorOf([&] { media::readFrames(path("garbage.mp4")); });
  EXPECT_NE(message.find("garbage.mp4: not a readable video"), std::string::npos) << message;
}

TEST_F(ImageIoTest, MissingFfmpegIsAClearError) {
  const char* previous = std::getenv("SMOKESVD_FFMPEG");
  const std::string saved = previous ? previous : "";
  ::setenv("SMOKESVD_FFMPEG", "/nonexistent/ffmpeg", 1);
  writeText(path("clip.mp4"), "x");
  const std::string message = errorOf([&] { media::readFrames(path("clip.mp4")); });
  const std::string writeMessage = errorOf([&] { media::writeVideo(path("out.mp4"), {ramp(4, 4)}); });
  if (previous) ::setenv("SMOKESVD_FFMPEG", saved.c_str(), 1);
  else ::unsetenv("SMOKESVD_FFMPEG");
  EXPECT_NE(message.find("SMOKESVD_FFMPEG=/nonexistent/ffmpeg is not an executable file"), std::string::npos) << message;
  EXPECT_NE(writeMessage.find("SMOKESVD_FFMPEG=/nonexistent/ffmpeg is not an executable file"), std::string::npos)
      << writeMessage;
  // Not configured and not on PATH.
  const std::string searchPath = std::getenv("PATH") ? std::getenv("PATH") : "";
  ::setenv("PATH", "/nonexistent", 1);
  ::unsetenv("SMOKESVD_FFMPEG");
  const std::string notFound = errorOf([&] { media::writeVideo(path("out.mp4"), {ramp(4, 4)}); });
  ::setenv("PATH", searchPath.c_str(), 1);
  if (previous) ::setenv("SMOKESVD_FFMPEG", saved.c_str(), 1);
  EXPECT_NE(notFound.find("needs ffmpeg, which was not found on PATH"), std::string::npos) << notFound;
}

TEST_F(ImageIoTest, VideoRoundTrip) {
  if (!media::findFfmpeg()) GTEST_SKIP() << "ffmpeg not installed";
  std::vector<media::Image> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(media::Image::gray(16, 10, 0.2f * static_cast<float>(i + 1)));
  media::writeVideo(path("clip.mp4"), frames, 10);
  EXPECT_FALSE(fs::exists(path("clip.mp4.tmp.mp4")));
  const media::VideoInfo info = media::probeVideo(path("clip.mp4"));
  EXPECT_EQ(info.width, 16);
  EXPECT_EQ(info.height, 10);
  EXPECT_NEAR(info.frameRate, 10.0, 1e-6);
  const std::vector<media::Image> back = media::readFrames(path("clip.mp4"), 1, 2);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back[0].values[5 * 16 + 8], 0.4, 0.03);
  EXPECT_NEAR(back[1].values[5 * 16 + 8], 0.6, 0.03);
}

}  // namespace
}  // namespace smokesvd::testing
