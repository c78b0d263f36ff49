#include <gtest/gtest.h>

#include <cmath>

#include "nets/optim/adam.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using optim::Adam;
using optim::AdamOptions;
using optim::LrSchedule;

// torch.optim.Adam / AdamW (single-tensor path) in double, one parameter tensor.
struct AdamReference {
  std::vector<double> p, m, v;
  int t = 0;

  void step(const AdamOptions& o, std::span<const float> grad, double clip) {
    const double lr = o.schedule.at(t);
    ++t;
    const double bc1 = 1 - std::pow(o.beta1, t), bc2 = 1 - std::pow(o.beta2, t);
    for (std::size_t i = 0; i < p.size(); ++i) {
      double g = grad[i] * clip;
      if (o.decoupledWeightDecay) p[i] *= 1 - lr * o.weightDecay;
      else g += o.weightDecay * p[i];
      m[i] = o.beta1 * m[i] + (1 - o.beta1) * g;
      v[i] = o.beta2 * v[i] + (1 - o.beta2) * g * g;
      p[i] -= lr / bc1 * m[i] / (std::sqrt(v[i]) / std::sqrt(bc2) + o.eps);
    }
  }
};

struct Case {
  std::string name;
  AdamOptions options;
  double maxNorm = 0;  // 0: no clipping
};

void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

class AdamTest : public GpuTest, public ::testing::WithParamInterface<Case> {};

// One training step is recorded once and submitted ten times with new gradients uploaded in between:
// parameters and both moments must follow the double reference after every step. A parameter without a
// gradient between the small ones splits their flat update into two runs; one at the end is a third case.
TEST_P(AdamTest, TenStepsMatchDoubleReference) {
  const Case& c = GetParam();
  // {4099} spans 3 workgroups; {140001} is large enough to be updated on its own, the others together.
  const std::vector<Shape> shapes = {{7}, {3, 5}, {1}, {140001}, {2, 3, 3, 3}, {4099}};
  NamedParameters parameters;
  std::vector<std::size_t> slot;  // where shapes[i]'s parameter is in `parameters`
  std::vector<AdamReference> references;
  std::vector<float> frozenValues, lastFrozenValues;
  Var frozen = variable(randomTensor(context(), {5}, 99, -1, 1, &frozenValues), true);  // never gets a gradient
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    if (i == 2) parameters.emplace_back("frozen", frozen);
    std::vector<float> initial;
    Var p = variable(randomTensor(context(), shapes[i], 10 + i, -1, 1, &initial), true);
    p->grad = Tensor(context(), shapes[i]);
    slot.push_back(parameters.size());
    parameters.emplace_back("p" + std::to_string(i), p);
    references.push_back({toDouble(initial), std::vector<double>(initial.size()), std::vector<double>(initial.size())});
  }
  Var lastFrozen = variable(randomTensor(context(), {3}, 98, -1, 1, &lastFrozenValues), true);
  parameters.emplace_back("last_frozen", lastFrozen);

  Adam adam(context(), parameters, c.options);
  optim::GradClip clip(context(), c.maxNorm > 0 ? c.maxNorm : 1.0);
  Stream stream(context());
  if (c.maxNorm > 0) clip.record(stream, parameters);
  adam.step(stream, c.maxNorm > 0 ? &clip : nullptr);

  for (int step = 0; step < 10; ++step) {
    std::vector<std::vector<float>> grads;
    double squares = 0;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      const float magnitude = std::pow(10.0f, static_cast<float>(step % 3) - 1.0f);
      grads.push_back(randomValues(static_cast<std::size_t>(numElements(shapes[i])), 100 * step + i, -magnitude,
                                   magnitude));
      parameters[slot[i]].second->grad.upload(grads.back());
      for (float g : grads.back()) squares += static_cast<double>(g) * g;
    }
    stream.submit();
    const double clipFactor = c.maxNorm > 0 ? std::min(1.0, c.maxNorm / (std::sqrt(squares) + 1e-6)) : 1.0;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      references[i].step(c.options, grads[i], clipFactor);
      const auto state = adam.namedState();
      const std::size_t k = slot[i];
      SCOPED_TRACE("step " + std::to_string(step + 1) + ", parameter " + parameters[k].first);
      EXPECT_TRUE(allClose(parameters[k].second->value, references[i].p, {2e-6, 2e-6}));
      // m sums terms of up to |g| = 10 that may cancel: float rounding of those terms bounds its error.
      EXPECT_EQ(state[2 * k].first, parameters[k].first + ".exp_avg");
      EXPECT_TRUE(allClose(state[2 * k].second, references[i].m, {1e-6, 1e-5}));
      EXPECT_TRUE(allClose(state[2 * k + 1].second, references[i].v, {1e-9, 1e-5}));
    }
  }
  EXPECT_EQ(adam.steps(), 10);
  EXPECT_NEAR(adam.lastLearningRate(), c.options.schedule.at(9), 1e-7);
  EXPECT_EQ(frozen->value.download(), frozenValues);
  EXPECT_EQ(lastFrozen->value.download(), lastFrozenValues);
  const auto state = adam.namedState();
  for (const std::size_t k : {std::size_t{2}, parameters.size() - 1}) {
    EXPECT_TRUE(allClose(state[2 * k].second, std::vector<double>(state[2 * k].second.numel(), 0.0), {0, 0}));
    EXPECT_TRUE(allClose(state[2 * k + 1].second, std::vector<double>(state[2 * k + 1].second.numel(), 0.0), {0, 0}));
  }
}

AdamOptions adam(double lr, double weightDecay = 0) {
  AdamOptions options;
  options.schedule = LrSchedule::constant(lr);
  options.weightDecay = weightDecay;
  return options;
}

AdamOptions withBetas(AdamOptions options, double beta1, double beta2, double eps) {
  options.beta1 = beta1;
  options.beta2 = beta2;
  options.eps = eps;
  return options;
}

INSTANTIATE_TEST_SUITE_P(
    Variants, AdamTest,
    ::testing::Values(Case{"Adam", adam(1e-2)}, Case{"AdamL2", adam(1e-2, 0.1)},
                      Case{"AdamW", AdamOptions::adamW(LrSchedule::constant(1e-2), 0.1)},
                      Case{"AdamWCosineWarmup", AdamOptions::adamW(LrSchedule::cosine(3e-2, 6, 1e-3, 3), 0.05)},
                      Case{"AdamLargeEpsOtherBetas", withBetas(adam(5e-3), 0.5, 0.9, 1e-3)},
                      Case{"AdamClipped", adam(1e-2), 0.05}, Case{"AdamWClipInactive",
                                                                AdamOptions::adamW(LrSchedule::constant(1e-2)), 1e3}),
    [](const ::testing::TestParamInfo<Case>& param) { return param.param.name; });

class AdamOptionsTest : public GpuTest {};

TEST_F(AdamOptionsTest, RejectsInvalidSettingsAndParameters) {
  Var p = variable(randomTensor(context(), {3}, 1), true);
  AdamOptions badBeta;
  badBeta.beta2 = 1.0;
  EXPECT_THROW(Adam(context(), {{"p", p}}, badBeta), Error);
  AdamOptions badDecay;
  badDecay.weightDecay = -1;
  EXPECT_THROW(Adam(context(), {{"p", p}}, badDecay), Error);
  Var constant = variable(randomTensor(context(), {3}, 1), false);
  try {
    Adam(context(), {{"head.weight", constant}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'head.weight' does not require a gradient"), std::string::npos);
  }
}

}  // namespace
}  // namespace smokesvd::testing
