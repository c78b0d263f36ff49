// Temporal metrics through OpenCV's Farneback flow: a texture moving one pixel per frame has a flow of about one
// pixel and a small warp error; a still sequence has none; a lone frame has no pair.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/eval/temporal_metrics.h"

namespace smokesvd::testing {
namespace {

media::Image texture(double shift, int width = 48, int height = 40) {
  media::Image image = media::Image::gray(width, height);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      const double x = c - shift;
      image.at(r, c) = static_cast<float>(0.5 + 0.25 * std::sin(0.45 * x) * std::cos(0.3 * r) + 0.2 * std::sin(0.17 * x + 0.21 * r));
    }
  return image;
}

TEST(TemporalMetricsTest, ATextureMovingOnePixelPerFrame) {
  if (!eval::opticalFlowAvailable()) GTEST_SKIP() << "built without OpenCV";
  eval::TemporalAccumulator moving, still;
  for (int t = 0; t < 5; ++t) {
    moving.add(texture(t));
    still.add(texture(0));
  }
  const eval::TemporalScores m = moving.finish(), s = still.finish();
  EXPECT_TRUE(m.available);
  EXPECT_EQ(m.pairs, 4);
  EXPECT_NEAR(m.flowMean, 1.0, 0.15);
  EXPECT_LE(m.flowMax, 1.2);
  EXPECT_LT(m.flowStd, 0.05);
  EXPECT_LT(m.warpError, 2e-4);
  // The same frames without warping differ by far more.
  double unwarped = 0;
  const media::Image a = texture(0), b = texture(1);
  for (std::size_t i = 0; i < a.values.size(); ++i) unwarped += (a.values[i] - b.values[i]) * (a.values[i] - b.values[i]);
  EXPECT_GT(unwarped / static_cast<double>(a.values.size()), 20 * m.warpError);
  EXPECT_LT(s.flowMax, 0.01);
  EXPECT_LT(s.warpError, 1e-6);
}

TEST(TemporalMetricsTest, OneFrameHasNoPair) {
  eval::TemporalAccumulator one;
  one.add(texture(0));
  const eval::TemporalScores s = one.finish();
  EXPECT_EQ(s.pairs, 0);
  EXPECT_EQ(s.flowMean, 0.0);
  EXPECT_EQ(s.warpError, 0.0);
  EXPECT_THROW(one.add(texture(0, 20, 20)), std::exception);
}

}  // namespace
}  // namespace smokesvd::testing
