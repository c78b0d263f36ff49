// Image metrics on the GPU against the formulas evaluated in double: MSE, PSNR and SSIM (Wang et al. 2004:
// Gaussian window 11, sigma 1.5, K1 0.01, K2 0.03, L 1, valid positions), on random pairs of odd sizes with the
// outputs poisoned first, and on a known pair.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/eval/image_metrics.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/eval/metric_reference.h"

namespace smokesvd::testing {
namespace {

class ImageMetricsTest : public GpuTest {};

TEST_F(ImageMetricsTest, MseAndSsimOfRandomStacksMatchTheDoubleFormulas) {
  const int n = 3, height = 23, width = 17;
  std::vector<float> a, b = randomValues(static_cast<std::size_t>(n * height * width), 8, 0.0f, 1.0f);
  const Tensor ta = randomTensor(context(), {n, height, width}, 7, 0.0f, 1.0f, &a);
  // b: a blurred, noisy, darker copy of a for two images, unrelated noise for the third.
  for (std::size_t i = 0; i < static_cast<std::size_t>(2 * height * width); ++i) b[i] = 0.7f * a[i] + 0.2f * b[i];
  const Tensor tb = Tensor::fromHost(context(), {n, height, width}, b);
  const Tensor mse = poisonedTensor(context(), {n}), ssim = poisonedTensor(context(), {n});
  Stream stream(context());
  eval::recordImageScores(stream, ta, tb, mse, ssim);
  stream.submit();
  std::vector<double> expectedMse, expectedSsim;
  const std::size_t pixels = static_cast<std::size_t>(height * width);
  for (int k = 0; k < n; ++k) {
    const std::vector<float> ak(a.begin() + k * pixels, a.begin() + (k + 1) * pixels), bk(b.begin() + k * pixels, b.begin() + (k + 1) * pixels);
    expectedMse.push_back(referenceMse(ak, bk));
    expectedSsim.push_back(referenceSsim(ak, bk, width, height));
  }
  EXPECT_TRUE(allClose(mse, expectedMse, {1e-6, 1e-5}));
  EXPECT_TRUE(allClose(ssim, expectedSsim, {1e-5, 1e-5}));
}

TEST_F(ImageMetricsTest, AKnownPairAndTheLimits) {
  // A ramp against the ramp plus a checkerboard of +-0.05: SSIM from the formula in double.
  const int width = 20, height = 14;
  std::vector<float> ramp, noisy;
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c) {
      ramp.push_back(static_cast<float>(c) / (width - 1));
      noisy.push_back(ramp.back() + ((r + c) % 2 ? 0.05f : -0.05f));
    }
  media::Image a = media::Image::gray(width, height), b = a, black = a;
  a.values = ramp;
  b.values = noisy;
  const std::vector<eval::ImagePair> pairs{{&a, &b}, {&a, &a}, {&black, &a}};
  const std::vector<eval::ImageScore> s = eval::compareImages(context(), pairs);
  EXPECT_NEAR(s[0].ssim, referenceSsim(ramp, noisy, width, height), 1e-5);
  EXPECT_NEAR(s[0].mse, 0.0025, 1e-7);
  EXPECT_NEAR(s[0].psnr(), 10 * std::log10(1 / 0.0025), 1e-4);
  EXPECT_NEAR(s[0].rmse(), 0.05, 1e-6);
  EXPECT_EQ(s[1].mse, 0.0);
  EXPECT_NEAR(s[1].ssim, 1.0, 1e-6);
  EXPECT_EQ(s[1].psnr(), eval::kPsnrCap);
  EXPECT_NEAR(s[2].mse, referenceMse(std::vector<float>(ramp.size(), 0.0f), ramp), 1e-6);
  EXPECT_NEAR(s[2].ssim, referenceSsim(std::vector<float>(ramp.size(), 0.0f), ramp, width, height), 1e-5);
}

TEST_F(ImageMetricsTest, PairsOfTwoSizesAndBadPairs) {
  media::Image small = media::Image::gray(12, 11, 0.5f), big = media::Image::gray(30, 16, 0.25f), tiny = media::Image::gray(10, 30);
  const std::vector<eval::ImagePair> pairs{{&small, &small}, {&big, &small}};
  EXPECT_THROW(eval::compareImages(context(), pairs), Error);
  media::Image big2 = big;
  big2.values[5] = 1.0f;
  const std::vector<eval::ImagePair> good{{&big, &big2}, {&small, &small}};
  const std::vector<eval::ImageScore> s = eval::compareImages(context(), good);
  EXPECT_NEAR(s[0].mse, 0.75 * 0.75 / (30 * 16), 1e-8);
  EXPECT_EQ(s[1].mse, 0.0);
  const std::vector<eval::ImagePair> narrow{{&tiny, &tiny}};
  try {
    eval::compareImages(context(), narrow);
    FAIL() << "a 10-pixel-wide image was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("smaller than the 11 x 11 SSIM window"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace smokesvd::testing
