#include <gtest/gtest.h>

#include "nets/functional/broadcast.h"
#include "nets/ops/broadcast.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using ops::BinaryOp;

class BroadcastTest : public GpuTest {};

double apply(BinaryOp op, double a, double b) {
  switch (op) {
    case BinaryOp::Add: return a + b;
    case BinaryOp::Sub: return a - b;
    case BinaryOp::Mul: return a * b;
    case BinaryOp::Div: return a / b;
  }
  return 0;
}

// Flat index into `operand` (aligned at the last axis, size-1 axes repeated) of output element `i`.
std::size_t sourceIndex(std::size_t i, const Shape& out, const Shape& operand) {
  std::size_t index = 0, stride = 1;
  const std::size_t offset = out.size() - operand.size();
  for (std::size_t axis = out.size(); axis-- > 0;) {
    const std::size_t coordinate = i % static_cast<std::size_t>(out[axis]);
    i /= static_cast<std::size_t>(out[axis]);
    if (axis < offset) continue;
    const int64_t extent = operand[axis - offset];
    if (extent != 1) index += coordinate * stride;
    stride *= static_cast<std::size_t>(extent);
  }
  return index;
}

std::vector<double> reference(BinaryOp op, std::span<const double> a, const Shape& shapeA, std::span<const double> b,
                              const Shape& shapeB) {
  const Shape out = ops::broadcastShape("test", shapeA, shapeB);
  std::vector<double> y(static_cast<std::size_t>(numElements(out)));
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = apply(op, a[sourceIndex(i, out, shapeA)], b[sourceIndex(i, out, shapeB)]);
  return y;
}

struct Pattern {
  Shape a, b;
};

// The UNet cases (per-channel, per-sample, per-sample-and-channel, 5D) plus a masked channel, a
// broadcast first operand, both broadcast, vec4-aligned rows and a scalar.
const std::vector<Pattern> kPatterns{
    {{3, 5, 7, 9}, {1, 5, 1, 1}}, {{3, 5, 7, 9}, {5, 1, 1}},  {{3, 5, 7, 9}, {3, 1, 1, 1}}, {{3, 5, 7, 9}, {3, 5, 1, 1}},
    {{2, 3, 5, 7, 9}, {1, 3, 1, 1, 1}}, {{3, 5, 7, 9}, {3, 1, 7, 9}}, {{1, 5, 1, 1}, {3, 5, 7, 9}},
    {{3, 1, 7, 1}, {1, 5, 1, 9}}, {{2, 3, 4, 8}, {1, 3, 1, 1}}, {{2, 3, 4, 8}, {2, 1, 4, 8}}, {{7, 9}, {1}}};

TEST_F(BroadcastTest, EveryOpAndPatternMatchesReference) {
  for (const Pattern& p : kPatterns) {
    for (BinaryOp op : {BinaryOp::Add, BinaryOp::Sub, BinaryOp::Mul, BinaryOp::Div}) {
      SCOPED_TRACE(toString(p.a) + " op " + std::to_string(static_cast<int>(op)) + " " + toString(p.b));
      std::vector<float> a, b;
      Tensor ta = randomTensor(context(), p.a, 1, -1, 1, &a);
      Tensor tb = randomTensor(context(), p.b, 2, 0.5f, 2, &b);  // away from 0 for div
      Tensor y = poisonedTensor(context(), ops::broadcastShape("test", p.a, p.b));
      Stream stream(context());
      ops::broadcastBinary(stream, op, ta, tb, y);
      stream.submit();
      EXPECT_TRUE(allClose(y, reference(op, toDouble(a), p.a, toDouble(b), p.b), {1e-6, 1e-6}));
    }
  }
}

// The shaders' division by multiply-high (shaders/nn/broadcast_index.glsl), replayed on the CPU.
TEST(FastDivisor, DividesExactlyBelow2To31) {
  const auto divide = [](uint32_t n, ops::FastDivisor d) {
    const uint32_t high = static_cast<uint32_t>((uint64_t{n} * d.multiplier) >> 32);
    return (d.multiplier == 0 ? n : high) >> d.shift;
  };
  const std::vector<float> random = randomValues(2000, 9, 0.0f, 1.0f);
  for (uint32_t d : {1u, 2u, 3u, 5u, 7u, 63u, 64u, 112u, 4095u, 4096u, 65537u, 1000003u, 0x7fffffffu}) {
    for (float r : random) {
      const uint32_t n = static_cast<uint32_t>(static_cast<double>(r) * 2147483647.0);
      ASSERT_EQ(divide(n, ops::fastDivisor(d)), n / d) << n << " / " << d;
    }
    for (uint64_t n : {uint64_t{0}, uint64_t{d} - 1, uint64_t{d}, 2 * uint64_t{d} - 1, uint64_t{0x7fffffff}}) {
      if (n > 0x7fffffff) continue;
      const auto small = static_cast<uint32_t>(n);
      ASSERT_EQ(divide(small, ops::fastDivisor(d)), small / d) << n << " / " << d;
    }
  }
}

TEST_F(BroadcastTest, ExpandRepeatsAlongAxes) {
  std::vector<float> x;
  Tensor tx = randomTensor(context(), {3, 1, 5}, 1, -1, 1, &x);
  Tensor y = poisonedTensor(context(), {2, 3, 7, 5});
  Stream stream(context());
  ops::expand(stream, tx, y);
  stream.submit();
  const std::vector<double> ones(14, 1.0);
  EXPECT_TRUE(allClose(y, reference(BinaryOp::Mul, toDouble(x), {3, 1, 5}, ones, {2, 1, 7, 1}), {0, 0}));
}

TEST_F(BroadcastTest, GradientsMatchFiniteDifferences) {
  for (const Pattern& p : {Pattern{{2, 3, 3, 5}, {1, 3, 1, 1}}, Pattern{{2, 3, 5}, {2, 1, 1}},
                           Pattern{{3, 1, 5}, {1, 2, 5}}}) {
    for (BinaryOp op : {BinaryOp::Add, BinaryOp::Sub, BinaryOp::Mul, BinaryOp::Div}) {
      SCOPED_TRACE(toString(p.a) + " op " + std::to_string(static_cast<int>(op)) + " " + toString(p.b));
      std::vector<float> a, b, g;
      Var va = variable(randomTensor(context(), p.a, 1, -1, 1, &a), true);
      Var vb = variable(randomTensor(context(), p.b, 2, 0.5f, 2, &b), true);
      Stream stream(context());
      Tape tape(stream);
      Var y = fn::broadcastBinary(tape, op, va, vb);
      Tensor upstream = randomTensor(context(), y->value.shape(), 3, -1, 1, &g);
      tape.backward({{y, upstream}});
      stream.submit();
      const std::vector<double> da = toDouble(a), db = toDouble(b), dg = toDouble(g);
      const auto fa = [&](std::span<const double> x) { return reference(op, x, p.a, db, p.b); };
      const auto fb = [&](std::span<const double> x) { return reference(op, da, p.a, x, p.b); };
      EXPECT_TRUE(allClose(va->grad, numericVjp(fa, da, dg), {1e-5, 1e-4}));
      EXPECT_TRUE(allClose(vb->grad, numericVjp(fb, db, dg), {1e-5, 1e-4}));
    }
  }
}

TEST_F(BroadcastTest, ChannelAndSampleVectors) {
  const Shape shape{2, 3, 5};
  std::vector<float> x, perChannel, perSampleChannel, perSample;
  Var vx = variable(randomTensor(context(), shape, 1, -1, 1, &x), true);
  Var vc = variable(randomTensor(context(), {3}, 2, -1, 1, &perChannel), true);
  Var vnc = variable(randomTensor(context(), {2, 3}, 3, -1, 1, &perSampleChannel), true);
  Var vn = variable(randomTensor(context(), {2}, 4, -1, 1, &perSample), true);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::mulSample(tape, fn::addChannel(tape, fn::mulChannel(tape, vx, vnc), vc), vn);
  tape.backward(y);
  stream.submit();
  std::vector<double> expected(x.size());
  for (int n = 0; n < 2; ++n)
    for (int c = 0; c < 3; ++c)
      for (int s = 0; s < 5; ++s) {
        const std::size_t i = static_cast<std::size_t>((n * 3 + c) * 5 + s);
        expected[i] = (x[i] * perSampleChannel[n * 3 + c] + perChannel[c]) * perSample[n];
      }
  EXPECT_TRUE(allClose(y->value, expected, {1e-6, 1e-6}));
  EXPECT_EQ(vc->grad.shape(), (Shape{3}));
  EXPECT_EQ(vnc->grad.shape(), (Shape{2, 3}));
  std::vector<double> channelGrad(3, 0.0);  // d/dv_c sum(y) = sum over n, s of w_n
  for (int n = 0; n < 2; ++n)
    for (int c = 0; c < 3; ++c) channelGrad[c] += 5.0 * perSample[n];
  EXPECT_TRUE(allClose(vc->grad, channelGrad, {1e-5, 1e-5}));

  Var wrong = variable(randomTensor(context(), {4}, 5));
  EXPECT_THROW(fn::addChannel(tape, vx, wrong), Error);
  EXPECT_THROW(fn::mulSample(tape, vx, wrong), Error);
  EXPECT_THROW(ops::broadcastShape("test", {2, 3}, {4, 3, 2}), Error);
}

TEST_F(BroadcastTest, ReshapeIsAViewWithReshapedGradient) {
  Var x = variable(randomTensor(context(), {2, 6}, 1), true);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::reshape(tape, x, {3, 4});
  EXPECT_EQ(y->value.shape(), (Shape{3, 4}));
  tape.backward(y);
  stream.submit();
  EXPECT_EQ(x->grad.shape(), (Shape{2, 6}));
  EXPECT_TRUE(allClose(x->grad, std::vector<double>(12, 1.0), {0, 0}));
  EXPECT_THROW(fn::reshape(tape, x, {5}), Error);
}

// The runner's broadcast ops and reshape, forward and backward, as a user calls them.
TEST(BroadcastCommand, RunsEveryOp) {
  const std::vector<float> x{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};  // [2, 3, 2]
  const io::NpyArray images = io::NpyArray::fromFloats({2, 3, 2}, x);
  const io::NpyArray ones = io::NpyArray::fromFloats({2, 3, 2}, std::vector<float>(12, 1.0f));
  const OpRun general = runOpCommand("broadcast", {{"a", images}, {"b", io::NpyArray::fromFloats({3, 1}, {1, 2, 3})},
                                                   {"grad_y", ones}},
                                     {"y", "grad_b"}, {"op=mul"});
  ASSERT_EQ(general.exitCode, 0) << general.err;
  EXPECT_EQ(general.outputs.at("y").floats, (std::vector<float>{1, 2, 6, 8, 15, 18, 7, 8, 18, 20, 33, 36}));
  EXPECT_EQ(general.outputs.at("grad_b").floats, (std::vector<float>{1 + 2 + 7 + 8, 3 + 4 + 9 + 10, 5 + 6 + 11 + 12}));

  const OpRun channel = runOpCommand("channel_broadcast", {{"x", images}, {"v", io::NpyArray::fromFloats({3}, {10, 20, 30})},
                                                           {"grad_y", ones}},
                                     {"y", "grad_v"}, {"op=add"});
  ASSERT_EQ(channel.exitCode, 0) << channel.err;
  EXPECT_EQ(channel.outputs.at("y").floats, (std::vector<float>{11, 12, 23, 24, 35, 36, 17, 18, 29, 30, 41, 42}));
  EXPECT_EQ(channel.outputs.at("grad_v").floats, (std::vector<float>{4, 4, 4}));

  const OpRun sample = runOpCommand("sample_broadcast", {{"x", images}, {"w", io::NpyArray::fromFloats({2, 1, 1}, {1, 2})}},
                                    {"y"}, {"op=div"});
  ASSERT_EQ(sample.exitCode, 0) << sample.err;
  EXPECT_EQ(sample.outputs.at("y").floats, (std::vector<float>{1, 2, 3, 4, 5, 6, 3.5f, 4, 4.5f, 5, 5.5f, 6}));

  const OpRun reshaped = runOpCommand("reshape", {{"x", images}}, {"y"}, {"shape=4,3"});
  ASSERT_EQ(reshaped.exitCode, 0) << reshaped.err;
  EXPECT_EQ(reshaped.outputs.at("y").shape, (Shape{4, 3}));
  EXPECT_EQ(reshaped.outputs.at("y").floats, x);
  EXPECT_NE(runOpCommand("broadcast", {{"a", images}, {"b", images}}, {"y"}, {"op=pow"}).exitCode, 0);
}

}  // namespace
}  // namespace smokesvd::testing
