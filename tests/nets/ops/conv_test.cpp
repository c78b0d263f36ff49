// Convolution kernels against plain CPU references in double: forward and weight gradient on odd shapes
// (every blocking gives the same result), backward passes against central finite differences on tiny shapes and against
// the analytic references on shapes large enough to exercise the register-blocked paths with tails.
#include <gtest/gtest.h>

#include <string>

#include "nets/ops/conv.h"
#include "nets/ops/conv_kernels.h"
#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/nets/ops/conv_reference.h"

namespace smokesvd::testing {
namespace {

constexpr Tolerance kTolerance{1e-4, 1e-4};

struct Case {
  Shape x;
  Shape w;
  ConvSpec spec;
  bool bias = false;
};

std::string describe(const Case& c) {
  return "x " + toString(c.x) + " w " + toString(c.w) + " stride " + std::to_string(c.spec.stride) + " padding " +
         std::to_string(c.spec.padding) + " output padding " + std::to_string(c.spec.outputPadding) +
         (c.bias ? " with bias" : "");
}

ops::ConvParams params(const ConvSpec& spec) { return {spec.stride, spec.padding, spec.outputPadding}; }

// Seeded random operands on the device with their double host copies.
struct Operand {
  Tensor tensor;
  std::vector<double> values;
};

Operand operand(Context& context, const Shape& shape, uint64_t seed) {
  std::vector<float> host;
  Operand o;
  o.tensor = randomTensor(context, shape, seed, -1, 1, &host);
  o.values = toDouble(host);
  return o;
}

class ConvTest : public GpuTest {
 protected:
  // Forward conv (or transposed conv) on the GPU against the reference, for each blocking.
  void checkForward(const Case& c, bool transposed, std::initializer_list<ops::ConvBlocking> blockings = {{}}) {
    const Operand x = operand(context(), c.x, 1), w = operand(context(), c.w, 2);
    const int64_t outChannels = transposed ? c.w[1] : c.w[0];
    const Operand b = operand(context(), {outChannels}, 3);
    const std::vector<double> noBias;
    const std::span<const double> bias = c.bias ? std::span<const double>(b.values) : std::span<const double>(noBias);
    const Shape yShape = transposed ? referenceConvTransposeOutputShape(c.x, c.w, c.spec)
                                    : referenceConvOutputShape(c.x, c.w, c.spec);
    const std::vector<double> expected = transposed ? convTransposeReference(x.values, c.x, w.values, c.w, bias, c.spec)
                                                    : convReference(x.values, c.x, w.values, c.w, bias, c.spec);
    for (const ops::ConvBlocking& blocking : blockings) {
      Tensor y = poisonedTensor(context(), yShape);
      Stream stream(context());
      const Tensor* biasTensor = c.bias ? &b.tensor : nullptr;
      if (transposed)
        ops::convTransposeForward(stream, x.tensor, w.tensor, biasTensor, params(c.spec), y, blocking);
      else
        ops::convForward(stream, x.tensor, w.tensor, biasTensor, params(c.spec), y, blocking);
      stream.submit();
      EXPECT_TRUE(allClose(y, expected, kTolerance))
          << describe(c) << " blocking " << blocking.pixels << "x" << blocking.channelVec4s << " fetch "
          << static_cast<int>(blocking.fetch);
    }
  }

  // Backward-input, -weight and -bias of conv (or transposed conv) against finite differences of the
  // double reference.
  void checkGradients(const Case& c, bool transposed) {
    const Operand x = operand(context(), c.x, 4), w = operand(context(), c.w, 5);
    const Shape yShape = transposed ? referenceConvTransposeOutputShape(c.x, c.w, c.spec)
                                    : referenceConvOutputShape(c.x, c.w, c.spec);
    const Operand dy = operand(context(), yShape, 6);
    const int64_t outChannels = yShape[1];
    auto reference = [&](std::span<const double> xv, std::span<const double> wv, std::span<const double> bv) {
      return transposed ? convTransposeReference(xv, c.x, wv, c.w, bv, c.spec)
                        : convReference(xv, c.x, wv, c.w, bv, c.spec);
    };
    const std::vector<double> zeroBias(static_cast<std::size_t>(outChannels), 0.0);
    const std::vector<double> expectedDx =
        numericVjp([&](std::span<const double> v) { return reference(v, w.values, {}); }, x.values, dy.values);
    const std::vector<double> expectedDw =
        numericVjp([&](std::span<const double> v) { return reference(x.values, v, {}); }, w.values, dy.values);
    const std::vector<double> expectedDb =
        numericVjp([&](std::span<const double> v) { return reference(x.values, w.values, v); }, zeroBias, dy.values);

    Tensor dx = poisonedTensor(context(), c.x);
    Tensor dw = poisonedTensor(context(), c.w);
    Tensor db = poisonedTensor(context(), {outChannels});
    Stream stream(context());
    if (transposed) {
      ops::convTransposeBackwardInput(stream, dy.tensor, w.tensor, params(c.spec), dx);
      ops::convTransposeBackwardWeight(stream, x.tensor, dy.tensor, params(c.spec), dw);
    } else {
      ops::convBackwardInput(stream, dy.tensor, w.tensor, params(c.spec), dx);
      ops::convBackwardWeight(stream, x.tensor, dy.tensor, params(c.spec), dw);
    }
    ops::convBackwardBias(stream, dy.tensor, db);
    stream.submit();
    EXPECT_TRUE(allClose(dx, expectedDx, kTolerance)) << "input gradient, " << describe(c);
    EXPECT_TRUE(allClose(dw, expectedDw, kTolerance)) << "weight gradient, " << describe(c);
    EXPECT_TRUE(allClose(db, expectedDb, kTolerance)) << "bias gradient, " << describe(c);
  }

  // Conv backward passes against the analytic references (the transposed reference for the input
  // gradient), on shapes too large for finite differences.
  void checkLargeBackward(const Case& c) {
    const Operand x = operand(context(), c.x, 7), w = operand(context(), c.w, 8);
    const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
    const Operand dy = operand(context(), yShape, 9);
    ConvSpec back = c.spec;
    back.outputPadding = static_cast<int>(c.x.back() - referenceConvTransposeOutputShape(yShape, c.w, c.spec).back());
    const std::vector<double> expectedDx = convTransposeReference(dy.values, yShape, w.values, c.w, {}, back);
    const std::vector<double> expectedDw = convWeightGradReference(x.values, c.x, dy.values, c.w, c.spec);
    Tensor dx = poisonedTensor(context(), c.x);
    Tensor dw = poisonedTensor(context(), c.w);
    Stream stream(context());
    ops::convBackwardInput(stream, dy.tensor, w.tensor, params(c.spec), dx);
    ops::convBackwardWeight(stream, x.tensor, dy.tensor, params(c.spec), dw);
    stream.submit();
    EXPECT_TRUE(allClose(dx, expectedDx, kTolerance)) << "input gradient, " << describe(c);
    EXPECT_TRUE(allClose(dw, expectedDw, {1e-3, 1e-4})) << "weight gradient, " << describe(c);
  }
};

TEST_F(ConvTest, Forward2dOddShapes) {
  for (const Case& c : {Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {1, 0}, true}, Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {1, 1}},
                        Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 0}}, Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 1}, true},
                        Case{{2, 3, 7, 9}, {5, 3, 1, 1}, {1, 0}, true}, Case{{2, 3, 7, 9}, {5, 3, 1, 1}, {2, 0}},
                        Case{{2, 3, 7, 9}, {5, 3, 2, 4}, {2, 1}, true}})
    checkForward(c, false);
}

TEST_F(ConvTest, Forward3dOddShapes) {
  for (const Case& c : {Case{{2, 3, 5, 6, 7}, {5, 3, 3, 3, 3}, {1, 1}, true},
                        Case{{2, 3, 5, 6, 7}, {5, 3, 3, 3, 3}, {2, 0}},
                        Case{{2, 3, 5, 6, 7}, {5, 3, 1, 1, 1}, {1, 0}, true},
                        Case{{2, 3, 5, 6, 7}, {5, 3, 2, 2, 2}, {2, 1}}})
    checkForward(c, false);
}

TEST_F(ConvTest, EveryBlockingGivesTheSameForward) {
  // Includes the CPU default (16 pixels x 1 vec4, fetching per input channel) and the GPU defaults
  // (4 and 8 x 1, per kernel row), each blocking in both fetch orders.
  using enum ops::DirectFetch;
  const std::initializer_list<ops::ConvBlocking> blockings{
      {1, 1, PerKernelRow}, {3, 3, PerKernelRow}, {4, 1, PerKernelRow},    {8, 1, PerKernelRow},
      {8, 4, PerKernelRow}, {16, 1, PerKernelRow}, {1, 1, PerInputChannel}, {3, 3, PerInputChannel},
      {4, 1, PerInputChannel}, {8, 1, PerInputChannel}, {8, 4, PerInputChannel}, {16, 1, PerInputChannel}};
  checkForward(Case{{2, 5, 6, 11}, {7, 5, 3, 3}, {1, 1}, true}, false, blockings);
  checkForward(Case{{1, 3, 5, 4, 9}, {5, 3, 3, 3, 3}, {2, 1}}, false, blockings);
  // Transposed: stride-2 phases with different tap counts each.
  checkForward(Case{{1, 4, 3, 4, 5}, {4, 6, 3, 3, 3}, {2, 1}, true}, true, blockings);
}

// The two fetch orders of the direct pass add the same products in the same order: equal to the bit, for
// the forward pass and the input gradient (through a leaky ReLU gate and an addend).
TEST_F(ConvTest, BothFetchOrdersGiveBitIdenticalResults) {
  const Shape xShape{2, 6, 5, 7, 9}, wShape{7, 6, 3, 3, 3};
  const Operand x = operand(context(), xShape, 21), w = operand(context(), wShape, 22), b = operand(context(), {7}, 23);
  ops::ConvParams p;
  p.padding = 1;
  p.inputSlope = 0.2f;
  const Shape yShape = ops::convOutputShape(xShape, wShape, p);
  const Operand dy = operand(context(), yShape, 24), addend = operand(context(), xShape, 25);
  std::vector<std::vector<float>> forward, inputGradient;
  for (const ops::DirectFetch fetch : {ops::DirectFetch::PerKernelRow, ops::DirectFetch::PerInputChannel}) {
    Tensor y = poisonedTensor(context(), yShape), dx = poisonedTensor(context(), xShape);
    Stream stream(context());
    ops::convForward(stream, x.tensor, w.tensor, &b.tensor, p, y, {8, 2, fetch});
    ops::convBackwardActivatedInput(stream, dy.tensor, w.tensor, x.tensor, p, dx, &addend.tensor, {8, 2, fetch});
    stream.submit();
    forward.push_back(y.download());
    inputGradient.push_back(dx.download());
  }
  EXPECT_EQ(forward[0], forward[1]);
  EXPECT_EQ(inputGradient[0], inputGradient[1]);
}

TEST_F(ConvTest, EveryBlockingGivesTheSameWeightGradient) {
  // Includes the CPU and GPU default for wide outputs (8 pixels x 4 vec4s) and the one for 12 channels (8 x 3).
  // The first two shapes split the rows into several chunks on every device; the third, with 130 input channels,
  // into one on a CPU device of up to 2 threads (the chunks aim at 64 invocations per thread there). The last
  // two have rows of 16 and 8 outputs, which blocks of 4, 8 and 16 pixels cover exactly (10 and 6 channels: the
  // last vec4 of channels partly past K).
  for (const Case& c : {Case{{2, 5, 6, 11}, {9, 5, 3, 3}, {1, 1}}, Case{{1, 3, 5, 4, 9}, {10, 3, 3, 3, 3}, {2, 1}},
                        Case{{1, 130, 5, 6}, {9, 130, 3, 3}, {1, 1}}, Case{{2, 3, 5, 16}, {10, 3, 3, 3}, {1, 1}},
                        Case{{1, 2, 3, 4, 15}, {6, 2, 3, 3, 3}, {2, 1}}}) {
    const Operand x = operand(context(), c.x, 10);
    const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
    const Operand dy = operand(context(), yShape, 11);
    const std::vector<double> expected = convWeightGradReference(x.values, c.x, dy.values, c.w, c.spec);
    for (const ops::ConvBlocking blocking :
         {ops::ConvBlocking{1, 1}, ops::ConvBlocking{3, 3}, ops::ConvBlocking{4, 2}, ops::ConvBlocking{8, 3},
          ops::ConvBlocking{8, 4}, ops::ConvBlocking{16, 1}}) {
      Tensor dw = poisonedTensor(context(), c.w);
      Stream stream(context());
      ops::convBackwardWeight(stream, x.tensor, dy.tensor, params(c.spec), dw, blocking);
      stream.submit();
      EXPECT_TRUE(allClose(dw, expected, kTolerance))
          << describe(c) << " blocking " << blocking.pixels << "x" << blocking.channelVec4s;
    }
  }
}

TEST_F(ConvTest, ForwardLargerShapesWithTails) {
  checkForward(Case{{1, 14, 21, 37}, {22, 14, 3, 3}, {1, 1}, true}, false);
  checkForward(Case{{2, 12, 20, 23}, {20, 12, 3, 3}, {2, 1}}, false);
  checkForward(Case{{1, 8, 9, 10, 19}, {13, 8, 3, 3, 3}, {1, 1}, true}, false);
}

// Rows of a multiple of 4 values are padded from vec4 reads shifted by (-padding) mod 4 (conv_pad's VEC4_SOURCE):
// paddings 0-4 cover every shift and one of a whole vec4; the backward passes pad dy the same way.
TEST_F(ConvTest, RowsOfVec4sArePaddedAtEveryShift) {
  for (const Case& c : {Case{{2, 3, 5, 8}, {4, 3, 3, 3}, {1, 0}, true}, Case{{1, 3, 5, 8}, {4, 3, 3, 3}, {1, 1}, true},
                        Case{{1, 2, 4, 12}, {3, 2, 5, 5}, {1, 2}}, Case{{1, 2, 4, 12}, {3, 2, 7, 7}, {1, 3}, true},
                        Case{{1, 2, 3, 8}, {3, 2, 9, 9}, {1, 4}}, Case{{2, 3, 6, 8}, {5, 3, 3, 3}, {2, 1}},
                        Case{{1, 2, 3, 5, 8}, {3, 2, 3, 3, 3}, {1, 1}, true}, Case{{1, 2, 4, 3, 12}, {3, 2, 3, 3, 3}, {2, 2}}})
    checkForward(c, false);
  for (const Case& c : {Case{{1, 2, 8, 8}, {3, 2, 3, 3}, {1, 1}}, Case{{1, 2, 4, 4, 8}, {2, 2, 3, 3, 3}, {2, 1}}})
    checkGradients(c, false);
  checkLargeBackward(Case{{1, 6, 9, 16}, {5, 6, 5, 5}, {1, 2}});
  checkForward(Case{{1, 4, 5, 8}, {4, 3, 4, 4}, {2, 1}, true}, true);
}

TEST_F(ConvTest, Backward2dMatchesFiniteDifferences) {
  for (const Case& c : {Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {1, 1}}, Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 1}},
                        Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 0}}, Case{{2, 3, 7, 9}, {5, 3, 1, 1}, {1, 0}},
                        Case{{1, 3, 8, 6}, {2, 3, 4, 4}, {2, 1}}, Case{{1, 2, 8, 7}, {3, 2, 3, 3}, {2, 0}}})
    checkGradients(c, false);
}

TEST_F(ConvTest, Backward3dMatchesFiniteDifferences) {
  for (const Case& c : {Case{{1, 2, 5, 4, 6}, {3, 2, 3, 3, 3}, {1, 1}}, Case{{1, 2, 5, 4, 6}, {3, 2, 3, 3, 3}, {2, 1}},
                        Case{{2, 2, 4, 3, 5}, {3, 2, 2, 2, 2}, {2, 0}}})
    checkGradients(c, false);
}

TEST_F(ConvTest, BackwardLargerShapesWithTails) {
  checkLargeBackward(Case{{1, 14, 21, 37}, {22, 14, 3, 3}, {1, 1}});
  checkLargeBackward(Case{{2, 12, 21, 23}, {20, 12, 3, 3}, {2, 1}});
  checkLargeBackward(Case{{1, 9, 9, 10, 19}, {13, 9, 3, 3, 3}, {1, 1}});
  checkLargeBackward(Case{{1, 6, 9, 11, 13}, {10, 6, 3, 3, 3}, {2, 1}});
}

TEST_F(ConvTest, TransposedForwardMatchesScatterReference) {
  for (const Case& c : {Case{{2, 3, 4, 5}, {3, 5, 3, 3}, {2, 1, 1}, true}, Case{{2, 3, 4, 5}, {3, 5, 2, 2}, {2, 0}},
                        Case{{2, 3, 4, 5}, {3, 5, 4, 4}, {2, 1}, true}, Case{{1, 3, 5, 6}, {3, 2, 3, 3}, {1, 1}},
                        Case{{1, 3, 3, 4, 5}, {3, 4, 3, 3, 3}, {2, 1, 1}, true},
                        Case{{1, 3, 3, 4, 5}, {3, 4, 2, 2, 2}, {2, 0}}, Case{{2, 5, 3, 4}, {5, 3, 1, 1}, {2, 0, 1}, true}})
    checkForward(c, true);
}

TEST_F(ConvTest, TransposedBackwardMatchesFiniteDifferences) {
  for (const Case& c : {Case{{2, 3, 4, 5}, {3, 5, 3, 3}, {2, 1, 1}}, Case{{2, 3, 4, 5}, {3, 5, 2, 2}, {2, 0}},
                        Case{{1, 2, 3, 3, 4}, {2, 3, 3, 3, 3}, {2, 1, 1}}, Case{{1, 2, 3, 3, 4}, {2, 3, 2, 2, 2}, {2, 0}}})
    checkGradients(c, true);
}

// 1^d kernels at stride 1 without padding on D*H*W a multiple of 4 take the pointwise kernels (no padded
// copy); K below, at and above a block, C odd, tails of position blocks and of weight-gradient segments.
// The input gradient (and the transposed forward) reads the weights in place when its output channels are a
// multiple of 4 (12 at 4 × 8: a block of 8 and one of 4 with a vec4 past the end; 17 by default: 12 + 5) and
// packs them otherwise.
TEST_F(ConvTest, PointwiseForwardEveryBlocking) {
  const std::initializer_list<ops::ConvBlocking> blockings{{}, {1, 1}, {4, 1}, {5, 3}, {8, 4}, {16, 2}};
  for (const Case& c : {Case{{2, 5, 4, 7}, {9, 5, 1, 1}, {1, 0}, true},
                        Case{{2, 3, 2, 3, 6}, {1, 3, 1, 1, 1}, {1, 0}, true},
                        Case{{1, 13, 4, 6, 10}, {6, 13, 1, 1, 1}, {1, 0}},
                        Case{{3, 4, 3, 4}, {17, 4, 1, 1}, {1, 0}, true}})
    checkForward(c, false, blockings);
  checkForward(Case{{2, 5, 4, 7}, {5, 3, 1, 1}, {1, 0}, true}, true, blockings);
  checkForward(Case{{2, 5, 4, 7}, {5, 12, 1, 1}, {1, 0}, true}, true, blockings);
  checkForward(Case{{1, 3, 3, 4, 5}, {3, 8, 1, 1, 1}, {1, 0}}, true, blockings);
}

TEST_F(ConvTest, PointwiseBackwardMatchesFiniteDifferences) {
  for (const Case& c : {Case{{2, 3, 4, 6}, {5, 3, 1, 1}, {1, 0}}, Case{{1, 2, 2, 2, 3}, {3, 2, 1, 1, 1}, {1, 0}},
                        Case{{2, 5, 2, 2}, {1, 5, 1, 1}, {1, 0}}})
    checkGradients(c, false);
  checkGradients(Case{{2, 3, 4, 6}, {3, 5, 1, 1}, {1, 0}}, true);
}

TEST_F(ConvTest, PointwiseBackwardLargerShapesWithTails) {
  checkLargeBackward(Case{{2, 22, 5, 6, 12}, {19, 22, 1, 1, 1}, {1, 0}});
  checkLargeBackward(Case{{1, 6, 14, 18, 20}, {7, 6, 1, 1, 1}, {1, 0}});
  checkLargeBackward(Case{{2, 9, 36, 40}, {2, 9, 1, 1}, {1, 0}});
  checkLargeBackward(Case{{1, 12, 6, 10, 14}, {7, 12, 1, 1, 1}, {1, 0}});
  checkLargeBackward(Case{{2, 8, 18, 20}, {5, 8, 1, 1}, {1, 0}});
}

// A convolution that reads its input through leaky ReLU (ConvParams::inputSlope), pointwise and direct, against
// the references run on the activated input: forward (also with an addend, convForwardPlus), weight gradient,
// and the input gradient, which is the plain one times the activation's derivative at x.
TEST_F(ConvTest, InputThroughLeakyReluAndAddendMatchTheReferenceOnTheActivatedInput) {
  constexpr double kSlope = 0.2;
  for (const Case& c : {Case{{2, 5, 3, 4, 5}, {7, 5, 1, 1, 1}, {1, 0}, true}, Case{{1, 3, 5, 6, 7}, {4, 3, 3, 3, 3}, {1, 1}, true},
                        Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 1}, true}, Case{{2, 9, 6, 6}, {3, 9, 1, 1}, {1, 0}, true},
                        Case{{1, 3, 5, 8}, {4, 3, 3, 3}, {1, 1}, true}}) {
    const Operand x = operand(context(), c.x, 13), w = operand(context(), c.w, 14), b = operand(context(), {c.w[0]}, 15);
    const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
    const Operand dy = operand(context(), yShape, 16), addend = operand(context(), yShape, 17);
    std::vector<double> activated = x.values;
    for (double& v : activated) v = v > 0 ? v : kSlope * v;
    ConvSpec back = c.spec;
    back.outputPadding = static_cast<int>(c.x.back() - referenceConvTransposeOutputShape(yShape, c.w, c.spec).back());
    const std::vector<double> expectedY = convReference(activated, c.x, w.values, c.w, b.values, c.spec);
    std::vector<double> expectedSum = expectedY;
    for (std::size_t i = 0; i < expectedSum.size(); ++i) expectedSum[i] += addend.values[i];
    const std::vector<double> expectedDw = convWeightGradReference(activated, c.x, dy.values, c.w, c.spec);
    std::vector<double> expectedDx = convTransposeReference(dy.values, yShape, w.values, c.w, {}, back);
    for (std::size_t i = 0; i < expectedDx.size(); ++i) expectedDx[i] *= x.values[i] > 0 ? 1.0 : kSlope;

    ops::ConvParams through = params(c.spec);
    through.inputSlope = static_cast<float>(kSlope);
    Tensor y = poisonedTensor(context(), yShape), sum = poisonedTensor(context(), yShape);
    Tensor dx = poisonedTensor(context(), c.x);
    Tensor dw = poisonedTensor(context(), c.w);
    Stream stream(context());
    ops::convForward(stream, x.tensor, w.tensor, &b.tensor, through, y);
    ops::convForwardPlus(stream, x.tensor, w.tensor, &b.tensor, addend.tensor, through, sum);
    ops::convBackwardActivatedInput(stream, dy.tensor, w.tensor, x.tensor, through, dx);
    ops::convBackwardWeight(stream, x.tensor, dy.tensor, through, dw);
    stream.submit();
    EXPECT_TRUE(allClose(y, expectedY, kTolerance)) << "forward, " << describe(c);
    EXPECT_TRUE(allClose(sum, expectedSum, kTolerance)) << "forward plus an addend, " << describe(c);
    EXPECT_TRUE(allClose(dx, expectedDx, kTolerance)) << "input gradient, " << describe(c);
    EXPECT_TRUE(allClose(dw, expectedDw, kTolerance)) << "weight gradient, " << describe(c);
    // The plain input gradient and the transposed convolutions have no input activation to apply.
    EXPECT_THROW(ops::convBackwardInput(stream, dy.tensor, w.tensor, through, dx), Error);
  }
}

// The weight gradient reads the padded copy of f(x) its forward kept (ops::PaddedInput) instead of padding x
// again: the same sums bit for bit, one dispatch fewer. The forward's rows of 16 pixels always cover the weight
// gradient's rows of 8; a copy made for rows of 1 pixel is narrower than they are for these output widths
// (9, 5, 9, 6: rounded up to 8 they pass the copy's width) and is not used. A pointwise convolution keeps nothing.
TEST_F(ConvTest, WeightGradientReadsThePaddingItsForwardKept) {
  for (const Case& c : {Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {1, 1}}, Case{{2, 3, 7, 9}, {5, 3, 3, 3}, {2, 1}},
                        Case{{1, 3, 5, 6, 9}, {4, 3, 3, 3, 3}, {1, 1}}, Case{{1, 2, 6, 5, 12}, {3, 2, 3, 3, 3}, {2, 1}}}) {
    for (const float slope : {1.0f, 0.2f}) {
      SCOPED_TRACE(describe(c) + " input slope " + std::to_string(slope));
      const Operand x = operand(context(), c.x, 21), w = operand(context(), c.w, 22);
      const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
      const Operand dy = operand(context(), yShape, 23);
      ops::ConvParams through = params(c.spec);
      through.inputSlope = slope;
      std::vector<double> activated = x.values;
      for (double& v : activated) v = v > 0 ? v : slope * v;
      const std::vector<double> expected = convWeightGradReference(activated, c.x, dy.values, c.w, c.spec);

      auto weightGradient = [&](const ops::PaddedInput* kept, uint32_t* dispatches) {
        Tensor dw = poisonedTensor(context(), c.w);
        Stream stream(context());
        ops::convBackwardWeight(stream, x.tensor, dy.tensor, through, dw, {}, kept);
        *dispatches = stream.dispatchCount();
        stream.submit();
        return dw.download();
      };
      uint32_t fresh = 0, reused = 0, narrow = 0;
      const std::vector<float> padsAgain = weightGradient(nullptr, &fresh);

      ops::PaddedInput kept, narrowKept;
      Tensor y = poisonedTensor(context(), yShape);
      Stream forward(context());
      ops::convForward(forward, x.tensor, w.tensor, nullptr, through, y, ops::ConvBlocking{16, 1}, &kept);
      ops::convForward(forward, x.tensor, w.tensor, nullptr, through, y, ops::ConvBlocking{1, 1}, &narrowKept);
      forward.submit();
      ASSERT_TRUE(kept.tensor.defined());
      const std::vector<float> fromKept = weightGradient(&kept, &reused);
      EXPECT_EQ(fromKept, padsAgain) << "the kept copy gives other sums";
      EXPECT_EQ(reused + 1, fresh) << "the kept copy was not read";
      EXPECT_TRUE(allClose(fromKept, expected, c.w, kTolerance));

      const std::vector<float> fromNarrow = weightGradient(&narrowKept, &narrow);
      EXPECT_EQ(narrow, fresh) << "a copy too narrow was read";
      EXPECT_EQ(fromNarrow, padsAgain);
    }
  }
  const Operand x = operand(context(), {1, 6, 4, 8}, 24), w = operand(context(), {3, 6, 1, 1}, 25);
  Tensor y = poisonedTensor(context(), {1, 3, 4, 8});
  ops::PaddedInput kept;
  Stream stream(context());
  ops::convForward(stream, x.tensor, w.tensor, nullptr, {}, y, {}, &kept);
  stream.submit();
  EXPECT_FALSE(kept.tensor.defined()) << "a pointwise convolution pads nothing";
}

// Packs w [A, B, taps] as the forward pass does (wp[b, t, a] = w[a, b, t]: a the output channel) or, `flipped`, as
// the stride-1 backward-input pass does (wp[a, t, b] = w[a, b, taps - 1 - t]: a the convolution's output channel,
// b its input channel, the taps flipped along every axis), padded to paddedK packed output channels, and compares
// every element with a plain loop.
void checkWeightPacking(Context& context, const Shape& w, int64_t paddedK, bool flipped) {
  SCOPED_TRACE("w " + toString(w) + " padded to " + std::to_string(paddedK) + (flipped ? ", flipped" : ""));
  ops::conv::WeightPacking packing;
  packing.sourceKernel = w.size() == 5 ? ops::conv::Int3{w[2], w[3], w[4]} : ops::conv::Int3{1, w[2], w[3]};
  packing.taps = packing.sourceKernel;
  const int64_t taps = packing.taps[0] * packing.taps[1] * packing.taps[2];
  const int64_t packedK = flipped ? w[1] : w[0], packedC = flipped ? w[0] : w[1];
  packing.outChannels = packedK;
  packing.inChannels = packedC;
  packing.strideK = flipped ? taps : w[1] * taps;
  packing.strideC = flipped ? w[1] * taps : taps;
  if (flipped)
    for (std::size_t axis = 0; axis < 3; ++axis) {
      packing.firstTap[axis] = packing.sourceKernel[axis] - 1;
      packing.tapStep[axis] = -1;
    }
  const Operand weight = operand(context, w, 26);
  Stream stream(context);
  const Tensor packed = ops::conv::packWeights(stream, weight.tensor, packing, paddedK);
  stream.submit();
  std::vector<double> expected(static_cast<std::size_t>(packedC * taps * paddedK), 0.0);
  for (int64_t c = 0; c < packedC; ++c)
    for (int64_t t = 0; t < taps; ++t)
      for (int64_t k = 0; k < packedK; ++k) {
        const int64_t source = flipped ? (c * w[1] + k) * taps + (taps - 1 - t) : (k * w[1] + c) * taps + t;
        expected[static_cast<std::size_t>((c * taps + t) * paddedK + k)] = weight.values[static_cast<std::size_t>(source)];
      }
  EXPECT_TRUE(allClose(packed, expected, {0, 0}));
}

// The forward pass's packing: rows of C taps values that are whole vec4s take conv_pack_rows (C 4 and 8; 3x3,
// 3x3x3 and 1x1 kernels; K 5, 9 and 16, with padded channels past K), the others conv_pack_weights (C 3 and 5).
TEST_F(ConvTest, ForwardWeightPackingIsTheTransposeOfTheWeight) {
  for (const auto& [w, paddedK] : {std::pair<Shape, int64_t>{{5, 4, 3, 3}, 8}, {{9, 8, 3, 3, 3}, 12}, {{16, 4, 1, 1}, 16},
                                   {{5, 3, 3, 3}, 8}, {{7, 5, 1, 1, 1}, 8}})
    checkWeightPacking(context(), w, paddedK, false);
}

// The stride-1 backward-input pass's packing: input channel counts that are multiples of 4 take conv_pack_flipped
// (4 and 8; 3x3 and 3x3x3 kernels, padded past them), the others conv_pack_weights (3 and 5).
TEST_F(ConvTest, BackwardInputWeightPackingFlipsTheTaps) {
  for (const auto& [w, paddedK] : {std::pair<Shape, int64_t>{{5, 4, 3, 3}, 8}, {{3, 8, 3, 3, 3}, 12}, {{6, 8, 3, 3}, 8},
                                   {{5, 3, 3, 3}, 4}, {{2, 5, 3, 3, 3}, 8}})
    checkWeightPacking(context(), w, paddedK, true);
}

// The bias gradient against a sum in double, on planes with and without a multiple of 4 positions, and on
// planes long enough that a lane's share passes the loop budget, so that the plane is split into chunks.
TEST_F(ConvTest, BiasGradientOnShortAndLongPlanes) {
  for (const Shape& shape : {Shape{3, 5, 1, 7}, Shape{2, 3, 4, 6}, Shape{1, 2, 1, 600001}, Shape{2, 3, 1, 1, 600000}}) {
    const Operand dy = operand(context(), shape, 12);
    const int64_t batch = shape[0], channels = shape[1];
    const int64_t plane = static_cast<int64_t>(dy.values.size()) / (batch * channels);
    std::vector<double> expected(static_cast<std::size_t>(channels), 0.0);
    for (int64_t n = 0; n < batch; ++n)
      for (int64_t k = 0; k < channels; ++k)
        for (int64_t p = 0; p < plane; ++p) expected[k] += dy.values[static_cast<std::size_t>((n * channels + k) * plane + p)];
    Tensor db = poisonedTensor(context(), {channels});
    Stream stream(context());
    ops::convBackwardBias(stream, dy.tensor, db);
    stream.submit();
    // float sums of up to 1.2 million values in [-1, 1]: rounding of order 1e-3 in the long ones
    EXPECT_TRUE(allClose(db, expected, {plane > 1000 ? 2e-2 : 1e-4, 1e-4})) << "dy " << toString(shape);
  }
}

// A recording packs a weight once for the convolutions that use it unchanged, and again after a command
// has written it: three convolutions of one input, the weight doubled in place after the second. The first
// two give the reference's output with one packing between them; the third, twice that.
TEST_F(ConvTest, PackedWeightsAreReusedUntilTheWeightIsWritten) {
  const Shape xShape{1, 3, 7, 9, 5}, wShape{5, 3, 3, 3, 3};
  std::vector<float> xValues, wValues;
  const Tensor x = randomTensor(context(), xShape, 41, -1, 1, &xValues);
  const Tensor w = randomTensor(context(), wShape, 42, -1, 1, &wValues);
  const ops::ConvParams params{1, 1};
  const Shape yShape = ops::convOutputShape(xShape, wShape, params);
  std::vector<Tensor> ys;
  for (int i = 0; i < 3; ++i) ys.push_back(poisonedTensor(context(), yShape));
  Stream stream(context());
  ops::convForward(stream, x, w, nullptr, params, ys[0]);
  const uint32_t first = stream.dispatchCount();
  ops::convForward(stream, x, w, nullptr, params, ys[1]);
  const uint32_t second = stream.dispatchCount() - first;
  ops::scale(stream, w, 2.0f, w);
  const uint32_t beforeThird = stream.dispatchCount();
  ops::convForward(stream, x, w, nullptr, params, ys[2]);
  EXPECT_EQ(second + 1, first);                                  // no packing the second time
  EXPECT_EQ(stream.dispatchCount() - beforeThird, first);        // packed again after the write
  stream.submit();
  std::vector<double> expected = convReference(toDouble(xValues), xShape, toDouble(wValues), wShape, {}, ConvSpec{1, 1});
  EXPECT_TRUE(allClose(ys[0], expected, {1e-5, 1e-5}));
  EXPECT_TRUE(allClose(ys[1], expected, {1e-5, 1e-5}));
  for (double& v : expected) v *= 2;
  EXPECT_TRUE(allClose(ys[2], expected, {1e-5, 1e-5}));
}

// Constant weights (a frozen network, Tensor::markConstant) are packed once, outside the recordings, and every
// later recording finds the packing: none of its own dispatches packs. A host write packs them again.
TEST_F(ConvTest, ConstantWeightsArePackedOnceForEveryRecordingUntilTheHostWritesThem) {
  const Shape xShape{1, 3, 7, 9, 5}, wShape{5, 3, 3, 3, 3};
  std::vector<float> xValues, wValues;
  const Tensor x = randomTensor(context(), xShape, 43, -1, 1, &xValues);
  const Tensor w = randomTensor(context(), wShape, 44, -1, 1, &wValues);
  const ops::ConvParams params{1, 1};
  const Shape yShape = ops::convOutputShape(xShape, wShape, params);
  uint32_t packing = 0;  // dispatches of a recording that packs the weights itself
  {
    Stream stream(context());
    ops::convForward(stream, x, w, nullptr, params, poisonedTensor(context(), yShape));
    packing = stream.dispatchCount();
  }
  w.markConstant();
  std::vector<double> expected = convReference(toDouble(xValues), xShape, toDouble(wValues), wShape, {}, ConvSpec{1, 1});
  for (int recording = 0; recording < 2; ++recording) {
    const Tensor y = poisonedTensor(context(), yShape);
    Stream stream(context());
    ops::convForward(stream, x, w, nullptr, params, y);
    EXPECT_EQ(stream.dispatchCount() + 1, packing) << "recording " << recording;
    stream.submit();
    stream.submit();
    EXPECT_TRUE(allClose(y, expected, {1e-5, 1e-5})) << "recording " << recording;
  }
  for (float& v : wValues) v *= -0.5f;
  w.upload(wValues);
  expected = convReference(toDouble(xValues), xShape, toDouble(wValues), wShape, {}, ConvSpec{1, 1});
  const Tensor y = poisonedTensor(context(), yShape);
  Stream stream(context());
  ops::convForward(stream, x, w, nullptr, params, y);
  stream.submit();
  EXPECT_TRUE(allClose(y, expected, {1e-5, 1e-5})) << "after the host wrote the weights";
}

TEST_F(ConvTest, ARecordedWriteToConstantWeightsIsRefused) {
  const Tensor w = randomTensor(context(), {5, 3, 3, 3}, 45, -1, 1);
  w.markConstant();
  Stream stream(context());
  try {
    ops::scale(stream, w, 2.0f, w);
    FAIL() << "the write was recorded";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("constant tensor"), std::string::npos) << message;
    EXPECT_NE(message.find("kernel '"), std::string::npos) << "names the kernel: " << message;
  }
}

TEST_F(ConvTest, RejectsMismatchedShapes) {
  Tensor x(context(), {1, 3, 8, 8});
  Tensor w(context(), {4, 2, 3, 3});
  Tensor y(context(), {1, 4, 6, 6});
  Stream stream(context());
  EXPECT_THROW(ops::convForward(stream, x, w, nullptr, {}, y), Error);
  Tensor w3(context(), {4, 3, 3, 3});
  Tensor wrongY(context(), {1, 4, 8, 8});
  EXPECT_THROW(ops::convForward(stream, x, w3, nullptr, {}, wrongY), Error);
  EXPECT_THROW(ops::convForward(stream, x, w3, nullptr, {0, 0}, y), Error);
  Tensor bias(context(), {3});
  EXPECT_THROW(ops::convForward(stream, x, w3, &bias, {}, y), Error);
  Tensor ty(context(), {1, 3, 16, 16});
  EXPECT_THROW(ops::convTransposeForward(stream, y, w3, nullptr, {2, 0, 2}, ty), Error);
}

}  // namespace
}  // namespace smokesvd::testing
