#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "nets/functional/activation.h"
#include "nets/io/npy.h"
#include "nets/ops/activation.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using ops::Activation;

class ActivationTest : public GpuTest {};

constexpr float kSlope = 0.2f;

double reference(Activation activation, double x) {
  const double s = 1.0 / (1.0 + std::exp(-x));
  switch (activation) {
    case Activation::Relu: return x > 0 ? x : 0.0;
    case Activation::LeakyRelu: return x > 0 ? x : kSlope * x;
    case Activation::Silu: return x * s;
    case Activation::Sigmoid: return s;
    case Activation::Tanh: return std::tanh(x);
  }
  return 0;
}

std::vector<double> referenceAll(Activation activation, std::span<const double> x) {
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) y[i] = reference(activation, x[i]);
  return y;
}

Var apply(Tape& tape, Activation activation, const Var& x) {
  switch (activation) {
    case Activation::Relu: return fn::relu(tape, x);
    case Activation::LeakyRelu: return fn::leakyRelu(tape, x, kSlope);
    case Activation::Silu: return fn::silu(tape, x);
    case Activation::Sigmoid: return fn::sigmoid(tape, x);
    case Activation::Tanh: return fn::tanh(tape, x);
  }
  return nullptr;
}

const Activation kAll[] = {Activation::Relu, Activation::LeakyRelu, Activation::Silu, Activation::Sigmoid,
                           Activation::Tanh};

// Random values in [-5, 5] kept at least 0.01 away from the kink at 0.
std::vector<float> awayFromZero(std::size_t n, uint64_t seed) {
  std::vector<float> values = randomValues(n, seed, -5.0f, 5.0f);
  for (float& v : values)
    if (std::abs(v) < 0.01f) v = 0.5f;
  return values;
}

TEST_F(ActivationTest, ForwardAndBackwardMatchReferenceAndFiniteDifferences) {
  const Shape shape{3, 5, 7};  // 105 elements: not a multiple of 4
  const std::vector<float> x = awayFromZero(105, 1);
  std::vector<float> g;
  const Tensor upstream = randomTensor(context(), shape, 2, -1, 1, &g);
  for (Activation activation : kAll) {
    SCOPED_TRACE(static_cast<int>(activation));
    Var vx = variable(Tensor::fromHost(context(), shape, x), true);
    Stream stream(context());
    Tape tape(stream);
    Var y = apply(tape, activation, vx);
    tape.backward({{y, upstream}});
    stream.submit();
    const std::vector<double> dx = toDouble(x);
    EXPECT_TRUE(allClose(y->value, referenceAll(activation, dx), {1e-6, 1e-5}));
    const auto expected = numericVjp([&](std::span<const double> p) { return referenceAll(activation, p); }, dx,
                                     toDouble(g));
    EXPECT_TRUE(allClose(vx->grad, expected, {1e-5, 1e-4}));
  }
}

TEST_F(ActivationTest, KernelsWriteEveryElementAndStayFiniteAtExtremes) {
  const std::vector<float> x{-1e30f, -100.0f, -30.0f, -1e-6f, 0.0f,   1e-6f,
                             0.1f,   0.24f,   0.26f,  30.0f, 100.0f, 1e30f, 3e-3f};
  const Shape shape{static_cast<int64_t>(x.size())};
  const Tensor input = Tensor::fromHost(context(), shape, x);
  const std::vector<float> ones(x.size(), 1.0f);
  const Tensor gy = Tensor::fromHost(context(), shape, ones);
  for (Activation activation : kAll) {
    SCOPED_TRACE(static_cast<int>(activation));
    Tensor y = poisonedTensor(context(), shape);
    Tensor gx = poisonedTensor(context(), shape);
    Stream stream(context());
    ops::activationForward(stream, activation, kSlope, input, y);
    ops::activationBackward(stream, activation, kSlope, input, gy, gx);
    stream.submit();
    std::vector<double> expected(x.size()), derivative(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      expected[i] = reference(activation, x[i]);
      // forms without cancellation in the tails: s (1 - s) = e / (1 + e)^2, 1 - tanh^2 = 1 / cosh^2
      const double v = x[i];
      const double e = std::exp(-std::abs(v));
      const double s = 1.0 / (1.0 + std::exp(-v));
      const double sigmoidDerivative = e / ((1 + e) * (1 + e));
      const double d[] = {v > 0 ? 1.0 : 0.0, v > 0 ? 1.0 : kSlope, s + v * sigmoidDerivative, sigmoidDerivative,
                          1.0 / (std::cosh(v) * std::cosh(v))};
      derivative[i] = d[static_cast<int>(activation)];
    }
    // relative tolerance: tanh and sigmoid keep their precision near 0
    EXPECT_TRUE(allClose(y, expected, {1e-30, 2e-6}));
    EXPECT_TRUE(allClose(gx, derivative, {1e-30, 2e-6}));
  }
}

TEST_F(ActivationTest, RunsThroughSmokesvdOp) {
  const Shape shape{2, 3, 5};
  const std::vector<float> x = awayFromZero(30, 3);
  const std::vector<float> g = randomValues(30, 4);
  struct Case {
    std::string op;
    std::vector<std::string> attrs;
    Activation activation;
  };
  const Case cases[] = {{"relu", {}, Activation::Relu},
                        {"leaky_relu", {"negative_slope=0.2"}, Activation::LeakyRelu},
                        {"silu", {}, Activation::Silu},
                        {"sigmoid", {}, Activation::Sigmoid},
                        {"tanh", {}, Activation::Tanh}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.op);
    const OpRun run = runOpCommand(
        c.op, {{"x", io::NpyArray::fromFloats(shape, x)}, {"grad_y", io::NpyArray::fromFloats(shape, g)}},
        {"y", "grad_x"}, c.attrs);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const std::vector<double> dx = toDouble(x);
    EXPECT_TRUE(allClose(run.outputs.at("y").floats, referenceAll(c.activation, dx), shape, {1e-6, 1e-5}));
    const auto expected =
        numericVjp([&](std::span<const double> p) { return referenceAll(c.activation, p); }, dx, toDouble(g));
    EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, expected, shape, {1e-5, 1e-4}));
  }
}

}  // namespace
}  // namespace smokesvd::testing
