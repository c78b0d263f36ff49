#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "nets/optim/adam.h"
#include "nets/optim/ema.h"
#include "nets/optim/grad_clip.h"
#include "nets/optim/schedule.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using optim::LrSchedule;

class OptimTest : public GpuTest {
 protected:
  // Parameters of the given shapes with random gradients; `grads` receives the host copies.
  NamedParameters withGradients(const std::vector<Shape>& shapes, float scale, std::vector<std::vector<float>>& grads) {
    NamedParameters parameters;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      Var p = variable(randomTensor(context(), shapes[i], 1 + i), true);
      grads.emplace_back();
      p->grad = randomTensor(context(), shapes[i], 50 + i, -scale, scale, &grads.back());
      parameters.emplace_back(std::string("p").append(std::to_string(i)), p);
    }
    return parameters;
  }
};

TEST_F(OptimTest, ClippingMatchesDoubleReference) {
  // One large gradient (several partial sums per tensor), odd small ones, and a parameter without one.
  const std::vector<Shape> shapes = {{1000003}, {3, 5}, {1}, {2, 3, 3}};
  for (const double maxNorm : {0.5, 1e6}) {
    std::vector<std::vector<float>> grads;
    NamedParameters parameters = withGradients(shapes, 0.01f, grads);
    parameters.emplace_back("no_grad", variable(randomTensor(context(), {4}, 9), true));
    double squares = 0;
    for (const auto& g : grads)
      for (float v : g) squares += static_cast<double>(v) * v;
    const double norm = std::sqrt(squares);
    const double factor = std::min(1.0, maxNorm / (norm + 1e-6));

    optim::GradClip clip(context(), maxNorm);
    Stream stream(context());
    clip.record(stream, parameters);
    clip.scaleGradients(stream, parameters);
    stream.submit();
    EXPECT_TRUE(allClose(clip.result(), std::vector<double>{norm, factor}, {0, 2e-6}));
    EXPECT_NEAR(clip.norm(), norm, 2e-6 * norm);
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      std::vector<double> expected = toDouble(grads[i]);
      for (double& g : expected) g *= factor;
      EXPECT_TRUE(allClose(parameters[i].second->grad, expected, {1e-9, 2e-6})) << "gradient " << i;
    }
  }
}

TEST_F(OptimTest, SharedGradientTensorIsScaledOnce) {
  std::vector<float> g;
  Tensor shared = randomTensor(context(), {6}, 3, -1, 1, &g);
  Var a = variable(randomTensor(context(), {6}, 1), true), b = variable(randomTensor(context(), {6}, 2), true);
  a->grad = shared;
  b->grad = shared;
  double squares = 0;
  for (float v : g) squares += 2.0 * v * v;
  const double factor = 0.1 / (std::sqrt(squares) + 1e-6);
  optim::GradClip clip(context(), 0.1);
  Stream stream(context());
  clip.record(stream, {{"a", a}, {"b", b}});
  clip.scaleGradients(stream, {{"a", a}, {"b", b}});
  stream.submit();
  std::vector<double> expected = toDouble(g);
  for (double& v : expected) v *= factor;
  EXPECT_TRUE(allClose(shared, expected, {1e-9, 2e-6}));
}

TEST_F(OptimTest, ClippingWithoutGradientsGivesFactorOne) {
  optim::GradClip clip(context(), 1.0);
  Stream stream(context());
  clip.record(stream, {{"p", variable(randomTensor(context(), {3}, 1), true)}});
  stream.submit();
  EXPECT_TRUE(allClose(clip.result(), std::vector<double>{0, 1}, {0, 0}));
  EXPECT_THROW(optim::GradClip(context(), 0.0), Error);
}

TEST_F(OptimTest, EmaFollowsDoubleReference) {
  // Small parameters (averaged together, flat) around a large one (averaged on its own).
  const std::vector<Shape> shapes = {{7}, {2, 3, 5}, {133001}, {1}};
  const double decay = 0.9;
  NamedParameters parameters;
  std::vector<std::vector<double>> shadows;
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    std::vector<float> values;
    Var p = variable(randomTensor(context(), shapes[i], i, -1, 1, &values), true);
    parameters.emplace_back("layer.p" + std::to_string(i), p);
    shadows.push_back(toDouble(values));
  }
  optim::Ema ema(context(), parameters, decay);
  Stream stream(context());
  ema.update(stream);
  for (int step = 0; step < 4; ++step) {
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      std::vector<float> values = randomValues(static_cast<std::size_t>(numElements(shapes[i])), 20 + 10 * step + i);
      parameters[i].second->value.upload(values);
      for (std::size_t k = 0; k < values.size(); ++k) shadows[i][k] += (1 - decay) * (values[k] - shadows[i][k]);
    }
    stream.submit();
  }
  const auto named = ema.namedShadows();
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    EXPECT_EQ(named[i].first, parameters[i].first);
    EXPECT_TRUE(allClose(named[i].second, shadows[i], {1e-6, 1e-6}));
  }
  Stream swap(context());
  ema.copyToParameters(swap);
  swap.submit();
  for (std::size_t i = 0; i < shapes.size(); ++i)
    EXPECT_TRUE(allClose(parameters[i].second->value, shadows[i], {1e-6, 1e-6})) << parameters[i].first;
  EXPECT_THROW(optim::Ema(context(), parameters, 1.5), Error);
}

TEST(LrScheduleTest, ClosedFormsOnTheHost) {
  const LrSchedule constant = LrSchedule::constant(0.1, 4);
  EXPECT_DOUBLE_EQ(constant.at(0), 0.025);
  EXPECT_DOUBLE_EQ(constant.at(3), 0.1);
  EXPECT_DOUBLE_EQ(constant.at(100), 0.1);

  const LrSchedule step = LrSchedule::step(0.1, 3, 0.5);  // torch StepLR(step_size=3, gamma=0.5)
  const double expectedStep[] = {0.1, 0.1, 0.1, 0.05, 0.05, 0.05, 0.025};
  for (int s = 0; s < 7; ++s) EXPECT_DOUBLE_EQ(step.at(s), expectedStep[s]) << s;

  const LrSchedule cosine = LrSchedule::cosine(0.1, 10, 0.01, 2);
  EXPECT_DOUBLE_EQ(cosine.at(0), 0.05);
  EXPECT_DOUBLE_EQ(cosine.at(2), 0.1);
  EXPECT_NEAR(cosine.at(7), 0.01 + 0.09 * 0.5 * (1 + std::cos(std::numbers::pi * 0.5)), 1e-15);
  EXPECT_DOUBLE_EQ(cosine.at(12), 0.01);
  EXPECT_DOUBLE_EQ(cosine.at(50), 0.01);

  EXPECT_THROW(LrSchedule::step(0.1, 0, 0.5).at(0), Error);
  EXPECT_THROW(LrSchedule::cosine(0.1, 0).at(0), Error);
  EXPECT_THROW(LrSchedule::constant(-1).at(0), Error);
}

// The GPU evaluates each schedule for 40 resubmissions of one recording; it must agree with the host formula.
TEST_F(OptimTest, GpuScheduleMatchesHostFormula) {
  for (const LrSchedule& schedule :
       {LrSchedule::constant(3e-4, 5), LrSchedule::step(1e-2, 7, 0.3, 3), LrSchedule::cosine(2e-3, 25, 1e-4, 6)}) {
    Var p = variable(randomTensor(context(), {3}, 1), true);
    optim::AdamOptions options;
    options.schedule = schedule;
    optim::Adam adam(context(), {{"p", p}}, options);
    Stream stream(context());
    adam.step(stream);
    for (int s = 0; s < 40; ++s) {
      stream.submit();
      EXPECT_NEAR(adam.lastLearningRate(), schedule.at(s), 1e-6 * schedule.baseLr) << "step " << s;
    }
  }
}

// Resuming at step n continues the bias corrections exactly as if n steps had run, even far out.
TEST_F(OptimTest, StepCounterResumesWithExactBiasCorrections) {
  Var p = variable(randomTensor(context(), {3}, 1), true);
  optim::AdamOptions options;
  options.schedule = LrSchedule::constant(1e-3);
  optim::Adam adam(context(), {{"p", p}}, options);
  for (const int64_t start : {int64_t{0}, int64_t{17}, int64_t{4999}, int64_t{200000}}) {
    adam.setSteps(start);
    Stream stream(context());
    adam.step(stream);
    for (int run = 0; run < 3; ++run) stream.submit();
    const double t = static_cast<double>(start + 3);
    const double c1 = 1 - std::pow(0.9, t), c2 = 1 - std::pow(0.999, t);
    EXPECT_EQ(adam.steps(), start + 3);
    EXPECT_TRUE(allClose(adam.scalars(), std::vector<double>{t, 1e-3, 1e-3 / c1, std::sqrt(c2), 1, c1, c2, 0},
                         {0, 1e-6}))
        << "resumed at " << start;
  }
  EXPECT_THROW(adam.setSteps(-1), Error);
}

}  // namespace
}  // namespace smokesvd::testing
