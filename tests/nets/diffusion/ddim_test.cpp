#include <gtest/gtest.h>

#include <cmath>

#include "nets/diffusion/ddim.h"
#include "nets/diffusion/forward_process.h"
#include "nets/diffusion/gaussian.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"
#include "nets/models/ddpm_unet.h"
#include "tests/harness/compare.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using diffusion::NoiseSchedule;

// The data distribution is one image x*; its exact noise prediction is eps(x_t) = (x_t - sqrt(abar_t) x*)
// / sqrt(1 - abar_t), whatever x_t is, so every clean estimate is x* and DDIM must end exactly on it.
class PointDenoiser : public diffusion::Denoiser {
 public:
  PointDenoiser(Context& context, const NoiseSchedule& schedule, Tensor target)
      : schedule_(schedule), target_(variable(std::move(target))),
        scaleTarget_(variable(Tensor(context, {1}))), inverseNoise_(variable(Tensor(context, {1}))) {}
  Var predictNoise(Tape& tape, const Var& x) override {
    return fn::mulSample(tape, fn::sub(tape, x, fn::mulSample(tape, target_, scaleTarget_)), inverseNoise_);
  }
  void setStep(int step) override {
    const double abar = schedule_.alphaBar(step);
    scaleTarget_->value.upload(std::vector<float>{static_cast<float>(std::sqrt(abar))});
    inverseNoise_->value.upload(std::vector<float>{static_cast<float>(1.0 / std::sqrt(1.0 - abar))});
    ++calls;
  }
  int calls = 0;

 private:
  const NoiseSchedule& schedule_;
  Var target_, scaleTarget_, inverseNoise_;
};

// A randomly initialised SvDiff-shaped network as a denoiser: its prediction depends on x and t.
class NetworkDenoiser : public diffusion::Denoiser {
 public:
  NetworkDenoiser(Context& context, models::DdpmUNet& net) : net_(net), t_(variable(Tensor(context, {1}))) {}
  Var predictNoise(Tape& tape, const Var& x) override { return net_.forward(tape, x, t_); }
  void setStep(int step) override { t_->value.upload(std::vector<float>{static_cast<float>(step)}); }

 private:
  models::DdpmUNet& net_;
  Var t_;
};

// Predicts no noise at all: every clean estimate is x_t / sqrt(abar_t).
class ZeroDenoiser : public diffusion::Denoiser {
 public:
  Var predictNoise(Tape& tape, const Var& x) override { return fn::scale(tape, x, 0.0f); }
  void setStep(int) override {}
};

class DdimTest : public GpuTest {};

TEST(NoiseScheduleTest, LinearScheduleMatchesItsDefinition) {
  const NoiseSchedule schedule = NoiseSchedule::linear(1000, 1e-4, 0.02);
  EXPECT_EQ(schedule.steps(), 1000);
  EXPECT_DOUBLE_EQ(schedule.beta(0), 1e-4);
  EXPECT_DOUBLE_EQ(schedule.beta(999), 0.02);
  double product = 1.0;
  for (int s = 0; s < 1000; ++s) {
    product *= 1.0 - (1e-4 + (0.02 - 1e-4) * s / 999.0);
    ASSERT_NEAR(schedule.alphaBar(s), product, 1e-15) << "step " << s;
  }
  EXPECT_NEAR(schedule.alphaBar(999), 4.0358e-5, 1e-8);  // the familiar DDPM value
  EXPECT_EQ(schedule.alphaBar(-1), 1.0);
  EXPECT_THROW(schedule.alphaBar(1000), Error);
  EXPECT_THROW(NoiseSchedule::linear(1), Error);
}

TEST(NoiseScheduleTest, UniformDdimStepsFollowTheReferenceStride) {
  const std::vector<int> steps = diffusion::ddimSteps(1000, 200);
  ASSERT_EQ(steps.size(), 200u);
  EXPECT_EQ(steps.front(), 0);
  EXPECT_EQ(steps[1], 5);
  EXPECT_EQ(steps.back(), 995);
  EXPECT_EQ(diffusion::ddimSteps(1000, 400).back(), 798);  // stride 2: the released code's 400-step call
  EXPECT_THROW(diffusion::ddimSteps(1000, 0), Error);
  EXPECT_THROW(diffusion::ddimSteps(1000, 1001), Error);
  // From a start step the steps spread over [0, start]: stride floor(401 / 20) = 20.
  const std::vector<int> fromStart = diffusion::ddimSteps(1000, 20, 400);
  ASSERT_EQ(fromStart.size(), 20u);
  EXPECT_EQ(fromStart[1], 20);
  EXPECT_EQ(fromStart.back(), 380);
  EXPECT_EQ(diffusion::ddimSteps(1000, 20, 999), diffusion::ddimSteps(1000, 20));
  EXPECT_THROW(diffusion::ddimSteps(1000, 402, 400), Error);
  // One step is the clean estimate from the highest step.
  EXPECT_EQ(diffusion::ddimSteps(1000, 1), std::vector<int>{999});
  EXPECT_EQ(diffusion::ddimSteps(1000, 1, 400), std::vector<int>{400});
}

TEST(NoiseScheduleTest, CleanEstimateInvertsTheForwardProcess) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  for (const int s : {0, 100, 500, 999}) {
    const double abar = schedule.alphaBar(s);
    const double noisy = std::sqrt(abar) * 0.3 + std::sqrt(1 - abar) * -1.7;
    EXPECT_NEAR(diffusion::cleanEstimate(schedule, s, noisy, -1.7), 0.3, 1e-9);
  }
}

TEST(GaussianTest, SeededNormalsHaveUnitMomentsAndRepeat) {
  diffusion::Gaussian a(7), b(7), c(8);
  const std::vector<float> x = a.values(200001), y = b.values(200001), z = c.values(16);
  EXPECT_EQ(x, y);
  EXPECT_NE(std::vector<float>(x.begin(), x.begin() + 16), z);
  double mean = 0, square = 0;
  for (const float v : x) {
    mean += v;
    square += static_cast<double>(v) * v;
  }
  mean /= static_cast<double>(x.size());
  square /= static_cast<double>(x.size());
  EXPECT_NEAR(mean, 0.0, 0.01);
  EXPECT_NEAR(square, 1.0, 0.01);
}

// The kernel against the formula, every element, outputs poisoned, odd size, with and without clipping.
TEST_F(DdimTest, StepKernelMatchesTheFormula) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  const Shape shape{1, 1, 7, 143};  // 1001 elements: the last vec4 is partial
  std::vector<float> x, eps, z;
  const Tensor xt = randomTensor(context(), shape, 1, -3, 3, &x), et = randomTensor(context(), shape, 2, -2, 2, &eps),
               zt = randomTensor(context(), shape, 3, -2, 2, &z);
  for (const bool clip : {false, true}) {
    diffusion::DdimOptions options;
    options.eta = 0.7;
    options.clipClean = clip;
    const std::vector<float> c = diffusion::ddimCoefficients(schedule, 600, 400, options);
    const Tensor coefficients = Tensor::fromHost(context(), {8}, c);
    const Tensor next = poisonedTensor(context(), shape), clean = poisonedTensor(context(), shape);
    Stream stream(context());
    diffusion::recordDdimStep(stream, xt, et, zt, coefficients, next, clean);
    stream.submit();

    const double abar = schedule.alphaBar(600), abarNext = schedule.alphaBar(400);
    const double sigma = 0.7 * std::sqrt((1 - abarNext) / (1 - abar)) * std::sqrt(1 - abar / abarNext);
    std::vector<double> expectedNext, expectedClean;
    for (std::size_t i = 0; i < x.size(); ++i) {
      double x0 = (x[i] - std::sqrt(1 - abar) * eps[i]) / std::sqrt(abar);
      if (clip) x0 = std::clamp(x0, -1.0, 1.0);
      expectedClean.push_back(x0);
      expectedNext.push_back(std::sqrt(abarNext) * x0 + std::sqrt(1 - abarNext - sigma * sigma) * eps[i] + sigma * z[i]);
    }
    EXPECT_TRUE(allClose(clean, expectedClean, {1e-5, 1e-5})) << "clip " << clip;
    EXPECT_TRUE(allClose(next, expectedNext, {1e-5, 1e-5})) << "clip " << clip;
  }
}

TEST_F(DdimTest, ReproducesTheCleanImageOfAKnownNoiseModelAtAnyEta) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  std::vector<float> target;
  const Tensor targetTensor = randomTensor(context(), {1, 1, 9, 5}, 11, -0.9f, 0.9f, &target);
  for (const double eta : {0.0, 1.0}) {
    for (const int steps : {1, 20, 1000}) {
      PointDenoiser denoiser(context(), schedule, targetTensor);
      diffusion::DdimOptions options;
      options.steps = steps;
      options.eta = eta;
      options.seed = 3;
      const Tensor sample = diffusion::ddimSample(context(), denoiser, schedule, {1, 1, 9, 5}, options);
      EXPECT_EQ(denoiser.calls, steps);
      EXPECT_TRUE(allClose(sample, target, {1e-4, 1e-4})) << "eta " << eta << ", " << steps << " steps";
    }
  }
}

// From a start image (SDEdit): the state begins as sqrt(abar_top) x_start + sqrt(1 - abar_top) z with z the
// seed's first draw. With no noise predicted and eta 0 every step keeps x / sqrt(abar_top), so the sample
// is x_start + sqrt((1 - abar_top) / abar_top) z exactly; the known-noise model still ends on its image.
TEST_F(DdimTest, StartsFromAnImageNoisedToTheHighestStep) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  const Shape shape{1, 2, 5, 7};
  std::vector<float> image, target;
  const Tensor start = randomTensor(context(), shape, 21, -1, 1, &image);
  const Tensor targetTensor = randomTensor(context(), shape, 22, -0.9f, 0.9f, &target);
  diffusion::DdimOptions options;
  options.steps = 2;  // steps 0 and 200 of [0, 400]
  options.start = 400;
  options.eta = 0;
  options.seed = 9;
  ZeroDenoiser zero;
  const Tensor sample = diffusion::ddimSample(context(), zero, schedule, shape, options, &start);
  const double abar = schedule.alphaBar(200);
  const std::vector<float> z = diffusion::Gaussian(9).values(image.size());
  std::vector<double> expected;
  for (std::size_t i = 0; i < image.size(); ++i) expected.push_back(image[i] + std::sqrt((1 - abar) / abar) * z[i]);
  EXPECT_TRUE(allClose(sample, expected, {1e-4, 1e-4}));

  for (const double eta : {0.0, 1.0}) {
    PointDenoiser denoiser(context(), schedule, targetTensor);
    options.steps = 20;
    options.eta = eta;
    EXPECT_TRUE(allClose(diffusion::ddimSample(context(), denoiser, schedule, shape, options, &start), target, {1e-4, 1e-4}))
        << "eta " << eta;
    EXPECT_EQ(denoiser.calls, 20);
  }
  options.steps = 402;
  EXPECT_THROW(diffusion::ddimSample(context(), zero, schedule, shape, options, &start), Error);
  options.steps = 20;
  EXPECT_THROW(diffusion::ddimSample(context(), zero, schedule, shape, options), Error);  // no start image
  EXPECT_THROW(diffusion::ddimSample(context(), zero, schedule, {1, 1, 5, 7}, options, &start), Error);
}

TEST_F(DdimTest, SamplingIsDeterministicForASeed) {
  models::DdpmUNetConfig config;
  config.inChannels = 1;
  config.channels = 8;
  config.channelMult = {1, 2};
  config.resBlocks = 1;
  config.groups = 4;
  models::DdpmUNet net(context(), config);
  net.initialize(5);
  // conv_out starts at zero (eps = 0 everywhere): give it weights so that the output depends on x and t.
  net.namedParameters().back().second->value.upload(randomValues(1, 9, 0.1f, 0.2f));
  net.namedParameters()[net.namedParameters().size() - 2].second->value.upload(randomValues(8 * 9, 10, -0.2f, 0.2f));
  const NoiseSchedule schedule = NoiseSchedule::linear();
  auto sample = [&](double eta, uint64_t seed) {
    NetworkDenoiser denoiser(context(), net);
    diffusion::DdimOptions options;
    options.steps = 10;
    options.eta = eta;
    options.seed = seed;
    return diffusion::ddimSample(context(), denoiser, schedule, {1, 1, 8, 6}, options).download();
  };
  EXPECT_EQ(sample(0.0, 1), sample(0.0, 1));
  EXPECT_EQ(sample(1.0, 1), sample(1.0, 1));
  EXPECT_NE(sample(1.0, 1), sample(1.0, 2));
  EXPECT_NE(sample(0.0, 1), sample(1.0, 1));
}

TEST_F(DdimTest, RefusesBadOptions) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  diffusion::DdimOptions options;
  options.steps = 0;
  EXPECT_THROW(options.validate(schedule), Error);
  options.steps = 10;
  options.eta = -1;
  EXPECT_THROW(options.validate(schedule), Error);
  options.eta = 0;
  options.clipClean = true;
  options.clipMin = 1;
  options.clipMax = -1;
  EXPECT_THROW(options.validate(schedule), Error);
}

TEST_F(DdimTest, ForwardProcessAndCleanEstimateAreInverse) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  const std::vector<int> steps{0, 250, 999};
  std::vector<float> clean;
  const Var x0 = variable(randomTensor(context(), {3, 1, 5, 7}, 4, -1, 1, &clean));
  const Var noise = variable(randomTensor(context(), {3, 1, 5, 7}, 5, -2, 2));
  const diffusion::StepFactorTensors factors(context(), 3);
  factors.upload(diffusion::stepFactors(schedule, steps));
  Stream stream(context());
  Tape tape(stream);
  const Var noisy = diffusion::addNoise(tape, x0, noise, factors);
  const Var estimate = diffusion::estimateClean(tape, noisy, noise, factors);
  stream.submit();
  // At step 999 the clean part is scaled by 0.0064, so float rounding of x_s grows by 1 / 0.0064.
  EXPECT_TRUE(allClose(estimate->value, clean, {2e-4, 1e-4}));
  const std::vector<float> n = noisy->value.download();
  const double abar = schedule.alphaBar(250);
  const std::vector<float> eps = noise->value.download();
  EXPECT_NEAR(n[35], std::sqrt(abar) * clean[35] + std::sqrt(1 - abar) * eps[35], 1e-5);
}

}  // namespace
}  // namespace smokesvd::testing
