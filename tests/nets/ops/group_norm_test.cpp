#include <gtest/gtest.h>

#include <cmath>

#include "nets/functional/activation.h"
#include "nets/functional/group_norm.h"
#include "nets/io/npy.h"
#include "nets/ops/group_norm.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/nets/ops/group_norm_reference.h"

namespace smokesvd::testing {
namespace {

class GroupNormTest : public GpuTest {};

struct Inputs {
  std::vector<float> x, gamma, beta;
};

Inputs randomInputs(const Shape& shape, uint64_t seed, float center = 0.0f, float spread = 1.0f) {
  const std::size_t c = static_cast<std::size_t>(shape[1]);
  return {randomValues(static_cast<std::size_t>(numElements(shape)), seed, center - spread, center + spread),
          randomValues(c, seed + 1, 0.5f, 1.5f), randomValues(c, seed + 2, -0.5f, 0.5f)};
}

struct Case {
  Shape shape;
  int64_t groups;
};

TEST_F(GroupNormTest, ForwardMatchesReference) {
  // plane sizes odd and multiples of 4 (the vec4 path), groups from 1 to C; groups of one chunk (up to 4096
  // elements: the stats pass writes the statistics) and of two (4230 and 5120 elements: the finalize pass
  // merges the chunks)
  for (const Case& t : {Case{{2, 6, 5, 7}, 3}, Case{{1, 4, 8, 8}, 4}, Case{{3, 4, 3, 3}, 1},
                        Case{{1, 6, 3, 5, 7}, 2}, Case{{2, 4, 9, 17, 11}, 2}, Case{{1, 2, 9, 60}, 1},
                        Case{{2, 4, 1, 1}, 2}, Case{{2, 4, 45, 47}, 2}, Case{{1, 2, 64, 40}, 1}}) {
    SCOPED_TRACE(toString(t.shape) + " groups " + std::to_string(t.groups));
    const Inputs in = randomInputs(t.shape, 1);
    const float eps = 1e-5f;
    const Shape c{t.shape[1]};
    Tensor y = poisonedTensor(context(), t.shape);
    Tensor stats = poisonedTensor(context(), {t.shape[0] * t.groups, 2});
    Stream stream(context());
    ops::groupNormForward(stream, Tensor::fromHost(context(), t.shape, in.x), Tensor::fromHost(context(), c, in.gamma),
                          Tensor::fromHost(context(), c, in.beta), t.groups, eps, y, stats);
    stream.submit();
    EXPECT_TRUE(allClose(y, groupNormReference(toDouble(in.x), toDouble(in.gamma), toDouble(in.beta),
                                               groupNormLayout(t.shape, t.groups), eps),
                         {2e-5, 2e-5}));
  }
}

TEST_F(GroupNormTest, LargeMeanInputsKeepTheirPrecision) {
  // values 1000 +- 1: a one-pass E[x^2] - E[x]^2 in float loses the variance entirely, and an unshifted
  // float sum of thousands of such values errs by ~1e-3 in the mean; the float mean itself is only
  // good to half an ulp of 1000 (3e-5), i.e. ~6e-5 in y
  for (const Case& t : {Case{{2, 4, 33, 65}, 2}, Case{{1, 2, 17, 19, 23}, 1}}) {
    SCOPED_TRACE(toString(t.shape));
    const Inputs in = randomInputs(t.shape, 2, 1000.0f, 1.0f);
    const Shape c{t.shape[1]};
    Tensor y = poisonedTensor(context(), t.shape);
    Tensor stats = poisonedTensor(context(), {t.shape[0] * t.groups, 2});
    Stream stream(context());
    ops::groupNormForward(stream, Tensor::fromHost(context(), t.shape, in.x), Tensor::fromHost(context(), c, in.gamma),
                          Tensor::fromHost(context(), c, in.beta), t.groups, 1e-5f, y, stats);
    stream.submit();
    EXPECT_TRUE(allClose(y, groupNormReference(toDouble(in.x), toDouble(in.gamma), toDouble(in.beta),
                                               groupNormLayout(t.shape, t.groups), 1e-5),
                         {1.5e-4, 0}));
  }
}

TEST_F(GroupNormTest, BackwardMatchesFiniteDifferences) {
  for (const Case& t : {Case{{2, 4, 3, 5}, 2}, Case{{1, 4, 3, 2, 5}, 2}, Case{{2, 3, 2, 2}, 3}}) {
    SCOPED_TRACE(toString(t.shape) + " groups " + std::to_string(t.groups));
    const Inputs in = randomInputs(t.shape, 3);
    const Shape c{t.shape[1]};
    std::vector<float> g;
    Var x = variable(Tensor::fromHost(context(), t.shape, in.x), true);
    Var gamma = variable(Tensor::fromHost(context(), c, in.gamma), true);
    Var beta = variable(Tensor::fromHost(context(), c, in.beta), true);
    const Tensor upstream = randomTensor(context(), t.shape, 4, -1, 1, &g);
    Stream stream(context());
    Tape tape(stream);
    const float eps = 1e-3f;
    Var y = fn::groupNorm(tape, x, gamma, beta, static_cast<int>(t.groups), eps);
    tape.backward({{y, upstream}});
    stream.submit();
    const GroupNormLayout l = groupNormLayout(t.shape, t.groups);
    const auto dx = toDouble(in.x), dgamma = toDouble(in.gamma), dbeta = toDouble(in.beta), dg = toDouble(g);
    EXPECT_TRUE(allClose(y->value, groupNormReference(dx, dgamma, dbeta, l, eps), {2e-5, 2e-5}));
    EXPECT_TRUE(allClose(x->grad,
                         numericVjp([&](auto p) { return groupNormReference(p, dgamma, dbeta, l, eps); }, dx, dg),
                         {1e-4, 1e-4}));
    EXPECT_TRUE(allClose(gamma->grad,
                         numericVjp([&](auto p) { return groupNormReference(dx, p, dbeta, l, eps); }, dgamma, dg),
                         {1e-4, 1e-4}));
    EXPECT_TRUE(allClose(beta->grad,
                         numericVjp([&](auto p) { return groupNormReference(dx, dgamma, p, l, eps); }, dbeta, dg),
                         {1e-4, 1e-4}));
  }
}

// The analytic gradients in double, for shapes too large for finite differences.
struct Gradients {
  std::vector<double> x, gamma, beta;
};

Gradients analyticBackward(std::span<const double> x, std::span<const double> gamma, std::span<const double> g,
                           const GroupNormLayout& l, double eps) {
  Gradients out{std::vector<double>(x.size()), std::vector<double>(gamma.size()), std::vector<double>(gamma.size())};
  const int64_t m = l.groupSize();
  for (int64_t b = 0; b < l.batch * l.groups; ++b) {
    const std::size_t first = static_cast<std::size_t>(b * m);
    double mean = 0, var = 0;
    for (int64_t i = 0; i < m; ++i) mean += x[first + i];
    mean /= static_cast<double>(m);
    for (int64_t i = 0; i < m; ++i) var += (x[first + i] - mean) * (x[first + i] - mean);
    const double rstd = 1.0 / std::sqrt(var / static_cast<double>(m) + eps);
    auto channel = [&](int64_t i) {
      return static_cast<std::size_t>((b % l.groups) * (l.channels / l.groups) + i / l.planeSize);
    };
    double m1 = 0, m2 = 0;
    for (int64_t i = 0; i < m; ++i) {
      const double xhat = (x[first + i] - mean) * rstd, h = g[first + i] * gamma[channel(i)];
      m1 += h / static_cast<double>(m);
      m2 += h * xhat / static_cast<double>(m);
      out.gamma[channel(i)] += g[first + i] * xhat;
      out.beta[channel(i)] += g[first + i];
    }
    for (int64_t i = 0; i < m; ++i) {
      const double xhat = (x[first + i] - mean) * rstd;
      out.x[first + i] = rstd * (g[first + i] * gamma[channel(i)] - m1 - xhat * m2);
    }
  }
  return out;
}

TEST_F(GroupNormTest, BackwardOnLargeShapesMatchesAnalyticGradients) {
  // planes of 9 x 17 x 31 = 4743 and 75 x 64 = 4800 elements: two chunks per plane; odd and vec4 paths
  for (const Case& t : {Case{{2, 4, 9, 17, 31}, 2}, Case{{1, 6, 75, 64}, 3}}) {
    SCOPED_TRACE(toString(t.shape));
    const Inputs in = randomInputs(t.shape, 5, 3.0f, 2.0f);
    const Shape c{t.shape[1]};
    std::vector<float> g;
    const Tensor x = Tensor::fromHost(context(), t.shape, in.x);
    const Tensor gamma = Tensor::fromHost(context(), c, in.gamma);
    const Tensor gy = randomTensor(context(), t.shape, 6, -1, 1, &g);
    Tensor y(context(), t.shape);
    Tensor stats(context(), {t.shape[0] * t.groups, 2});
    Tensor gx = poisonedTensor(context(), t.shape);
    Tensor ggamma = poisonedTensor(context(), c);
    Tensor gbeta = poisonedTensor(context(), c);
    Stream stream(context());
    ops::groupNormForward(stream, x, gamma, Tensor::fromHost(context(), c, in.beta), t.groups, 1e-5f, y, stats);
    ops::groupNormBackward(stream, x, gamma, Tensor::fromHost(context(), c, in.beta), stats, t.groups, gy, gx, ggamma,
                           gbeta);
    stream.submit();
    const Gradients expected =
        analyticBackward(toDouble(in.x), toDouble(in.gamma), toDouble(g), groupNormLayout(t.shape, t.groups), 1e-5);
    EXPECT_TRUE(allClose(gx, expected.x, {1e-4, 1e-4}));
    EXPECT_TRUE(allClose(ggamma, expected.gamma, {1e-3, 1e-4}));
    EXPECT_TRUE(allClose(gbeta, expected.beta, {1e-3, 1e-4}));
  }
}

TEST_F(GroupNormTest, SiluAfterTheNormMatchesReferenceAndFiniteDifferences) {
  // odd planes (the scalar path), planes of a multiple of 4 (vec4), several chunks per plane, 2D and 3D;
  // the norm's outputs spread to +-4 so that SiLU's curved part and both tails are reached
  for (const Case& t : {Case{{2, 4, 3, 5}, 2}, Case{{1, 4, 3, 2, 4}, 2}, Case{{2, 3, 2, 2}, 3},
                        Case{{1, 2, 9, 17, 31}, 1}}) {
    SCOPED_TRACE(toString(t.shape) + " groups " + std::to_string(t.groups));
    Inputs in = randomInputs(t.shape, 11);
    for (float& g : in.gamma) g *= 2.5f;
    const Shape c{t.shape[1]};
    std::vector<float> g;
    const float eps = 1e-3f;
    const Tensor x = Tensor::fromHost(context(), t.shape, in.x);
    const Tensor gamma = Tensor::fromHost(context(), c, in.gamma);
    const Tensor beta = Tensor::fromHost(context(), c, in.beta);
    const Tensor gy = randomTensor(context(), t.shape, 12, -1, 1, &g);
    Tensor y = poisonedTensor(context(), t.shape);
    Tensor stats = poisonedTensor(context(), {t.shape[0] * t.groups, 2});
    Tensor gx = poisonedTensor(context(), t.shape);
    Tensor ggamma = poisonedTensor(context(), c);
    Tensor gbeta = poisonedTensor(context(), c);
    Stream stream(context());
    ops::groupNormForward(stream, x, gamma, beta, t.groups, eps, y, stats, ops::NormActivation::Silu);
    ops::groupNormBackward(stream, x, gamma, beta, stats, t.groups, gy, gx, ggamma, gbeta, ops::NormActivation::Silu);
    stream.submit();
    const GroupNormLayout l = groupNormLayout(t.shape, t.groups);
    const auto dx = toDouble(in.x), dgamma = toDouble(in.gamma), dbeta = toDouble(in.beta), dg = toDouble(g);
    EXPECT_TRUE(allClose(y, groupNormSiluReference(dx, dgamma, dbeta, l, eps), {5e-5, 2e-5}));
    // the norm's gradient of gz = gy SiLU'(z), z the reference norm output
    std::vector<double> gz = groupNormReference(dx, dgamma, dbeta, l, eps);
    for (std::size_t i = 0; i < gz.size(); ++i) {
      const double s = 1.0 / (1.0 + std::exp(-gz[i]));
      gz[i] = dg[i] * s * (1.0 + gz[i] * (1.0 - s));
    }
    const Gradients expected = analyticBackward(dx, dgamma, gz, l, eps);
    EXPECT_TRUE(allClose(gx, expected.x, {2e-4, 1e-4}));
    EXPECT_TRUE(allClose(ggamma, expected.gamma, {1e-3, 1e-4}));
    EXPECT_TRUE(allClose(gbeta, expected.beta, {1e-3, 1e-4}));
    if (numElements(t.shape) > 1000) continue;  // finite differences on the small shapes
    EXPECT_TRUE(allClose(gx,
                         numericVjp([&](auto p) { return groupNormSiluReference(p, dgamma, dbeta, l, eps); }, dx, dg),
                         {2e-4, 1e-4}));
    EXPECT_TRUE(allClose(ggamma,
                         numericVjp([&](auto p) { return groupNormSiluReference(dx, p, dbeta, l, eps); }, dgamma, dg),
                         {2e-4, 1e-4}));
    EXPECT_TRUE(allClose(gbeta,
                         numericVjp([&](auto p) { return groupNormSiluReference(dx, dgamma, p, l, eps); }, dbeta, dg),
                         {2e-4, 1e-4}));
  }
}

// The fused norm-then-SiLU gives the norm followed by nn/activation's SiLU: the same bits forward, the
// gradients to float rounding (the backward recomputes z, and the compiler may contract it differently).
TEST_F(GroupNormTest, SiluAfterTheNormAgreesWithTheNormThenTheActivation) {
  for (const Case& t : {Case{{2, 4, 5, 7}, 2}, Case{{1, 8, 4, 6, 8}, 4}}) {
    SCOPED_TRACE(toString(t.shape));
    const Inputs in = randomInputs(t.shape, 13, 0.5f, 3.0f);
    const Shape c{t.shape[1]};
    const Tensor upstream = randomTensor(context(), t.shape, 14, -1, 1);
    std::vector<std::vector<float>> results[2];
    for (const bool fused : {false, true}) {
      Var x = variable(Tensor::fromHost(context(), t.shape, in.x), true);
      Var gamma = variable(Tensor::fromHost(context(), c, in.gamma), true);
      Var beta = variable(Tensor::fromHost(context(), c, in.beta), true);
      Stream stream(context());
      Tape tape(stream);
      const int groups = static_cast<int>(t.groups);
      Var y = fused ? fn::groupNormSilu(tape, x, gamma, beta, groups)
                    : fn::silu(tape, fn::groupNorm(tape, x, gamma, beta, groups));
      tape.backward({{y, upstream}});
      stream.submit();
      results[fused] = {y->value.download(), x->grad.download(), gamma->grad.download(), beta->grad.download()};
    }
    EXPECT_EQ(results[0][0], results[1][0]);
    for (std::size_t k = 1; k < results[0].size(); ++k)
      EXPECT_TRUE(allClose(std::span<const float>(results[1][k]), std::span<const float>(results[0][k]),
                           Shape{static_cast<int64_t>(results[0][k].size())}, {1e-6, 1e-6}))
          << "gradient " << k;
  }
}

TEST_F(GroupNormTest, AbsentParametersMeanNoAffineAndBadShapesAreErrors) {
  const Shape shape{1, 4, 3, 5};
  const Inputs in = randomInputs(shape, 7);
  Var x = variable(Tensor::fromHost(context(), shape, in.x), true);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::groupNorm(tape, x, nullptr, nullptr, 2);
  stream.submit();
  const std::vector<double> ones(4, 1.0), zeros(4, 0.0);
  EXPECT_TRUE(allClose(y->value, groupNormReference(toDouble(in.x), ones, zeros, groupNormLayout(shape, 2), 1e-5),
                       {2e-5, 2e-5}));
  EXPECT_THROW(fn::groupNorm(tape, x, nullptr, nullptr, 3), Error);
  Var wrongGamma = variable(Tensor::fromHost(context(), {3}, std::vector<float>{1, 1, 1}));
  EXPECT_THROW(fn::groupNorm(tape, x, wrongGamma, nullptr, 2), Error);
}

TEST_F(GroupNormTest, RunsThroughSmokesvdOp) {
  const Shape shape{2, 4, 3, 5};
  const Inputs in = randomInputs(shape, 8);
  const std::vector<float> g = randomValues(120, 9);
  const OpRun run = runOpCommand("group_norm",
                                 {{"x", io::NpyArray::fromFloats(shape, in.x)},
                                  {"gamma", io::NpyArray::fromFloats({4}, in.gamma)},
                                  {"beta", io::NpyArray::fromFloats({4}, in.beta)},
                                  {"grad_y", io::NpyArray::fromFloats(shape, g)}},
                                 {"y", "grad_x", "grad_gamma", "grad_beta"}, {"groups=2", "eps=1e-3"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const GroupNormLayout l = groupNormLayout(shape, 2);
  const auto dx = toDouble(in.x), dgamma = toDouble(in.gamma), dbeta = toDouble(in.beta);
  EXPECT_TRUE(
      allClose(run.outputs.at("y").floats, groupNormReference(dx, dgamma, dbeta, l, 1e-3), shape, {2e-5, 2e-5}));
  const Gradients expected = analyticBackward(dx, dgamma, toDouble(g), l, 1e-3);
  EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, expected.x, shape, {1e-4, 1e-4}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_gamma").floats, expected.gamma, {4}, {1e-4, 1e-4}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_beta").floats, expected.beta, {4}, {1e-4, 1e-4}));
}

}  // namespace
}  // namespace smokesvd::testing
