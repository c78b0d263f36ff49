// A convolution that reads its input through GroupNorm then SiLU (ops::convForwardOfNormSilu,
// convBackwardWeightOfNormSilu; the padding copy shaders/nn/conv_pad.comp with ACTIVATION 2) against the
// plain double references run on the normalised, activated input, and against the two ops it replaces.
#include <gtest/gtest.h>

#include "nets/functional/conv.h"
#include "nets/functional/group_norm.h"
#include "nets/functional/norm_silu_conv.h"
#include "nets/ops/conv.h"
#include "nets/ops/group_norm.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/nets/ops/conv_reference.h"
#include "tests/nets/ops/group_norm_reference.h"

namespace smokesvd::testing {
namespace {

class NormSiluConvTest : public GpuTest {};

struct Case {
  Shape x, w;
  ConvSpec spec;
  int64_t groups;
};

struct Operand {
  Tensor tensor;
  std::vector<double> values;
};

Operand operand(Context& context, const Shape& shape, uint64_t seed, float lo = -1, float hi = 1) {
  std::vector<float> host;
  Operand o;
  o.tensor = randomTensor(context, shape, seed, lo, hi, &host);
  o.values = toDouble(host);
  return o;
}

// 2D and 3D, odd and 4-aligned rows (the pad's scalar and vec4 paths), paddings 1 and 2, stride 2, one and
// several groups; the norm's outputs spread so that SiLU's curve and both tails are reached.
const Case kCases[] = {{{2, 4, 5, 7}, {3, 4, 3, 3}, {1, 1}, 2},      {{1, 6, 6, 8}, {5, 6, 3, 3}, {1, 2}, 3},
                       {{1, 3, 5, 6, 7}, {4, 3, 3, 3, 3}, {1, 1}, 1}, {{2, 4, 4, 5, 8}, {2, 4, 3, 3, 3}, {2, 1}, 4},
                       {{1, 2, 9, 12}, {3, 2, 3, 3}, {2, 1}, 1}};

TEST_F(NormSiluConvTest, ForwardAndWeightGradientMatchTheReferenceOnTheNormalisedInput) {
  constexpr float kEps = 1e-5f;
  for (const Case& c : kCases) {
    SCOPED_TRACE("x " + toString(c.x) + " w " + toString(c.w) + " groups " + std::to_string(c.groups));
    const Operand x = operand(context(), c.x, 1), w = operand(context(), c.w, 2), b = operand(context(), {c.w[0]}, 3);
    const Operand gamma = operand(context(), {c.x[1]}, 4, 0.5f, 2.5f), beta = operand(context(), {c.x[1]}, 5);
    const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
    const Operand dy = operand(context(), yShape, 6), addend = operand(context(), yShape, 7);
    const std::vector<double> activated =
        groupNormSiluReference(x.values, gamma.values, beta.values, groupNormLayout(c.x, c.groups), kEps);
    const std::vector<double> expectedY = convReference(activated, c.x, w.values, c.w, b.values, c.spec);
    std::vector<double> expectedSum = expectedY;
    for (std::size_t i = 0; i < expectedSum.size(); ++i) expectedSum[i] += addend.values[i];
    const std::vector<double> expectedDw = convWeightGradReference(activated, c.x, dy.values, c.w, c.spec);

    const ops::ConvParams params{c.spec.stride, c.spec.padding};
    Tensor stats = poisonedTensor(context(), {c.x[0] * c.groups, 2});
    Tensor y = poisonedTensor(context(), yShape), sum = poisonedTensor(context(), yShape);
    Tensor dw = poisonedTensor(context(), c.w), dwFromKept = poisonedTensor(context(), c.w);
    Stream stream(context());
    ops::groupNormStats(stream, x.tensor, c.groups, kEps, stats);
    const ops::NormSiluInput norm{&stats, &gamma.tensor, &beta.tensor, c.groups};
    ops::PaddedInput kept;
    ops::convForwardOfNormSilu(stream, x.tensor, norm, w.tensor, &b.tensor, nullptr, params, y, {}, &kept);
    ops::convForwardOfNormSilu(stream, x.tensor, norm, w.tensor, &b.tensor, &addend.tensor, params, sum);
    const uint32_t start = stream.dispatchCount();
    ops::convBackwardWeightOfNormSilu(stream, x.tensor, norm, dy.tensor, params, dw);
    const uint32_t between = stream.dispatchCount();
    ops::convBackwardWeightOfNormSilu(stream, x.tensor, norm, dy.tensor, params, dwFromKept, {}, &kept);
    const uint32_t padsAgain = between - start, fromKept = stream.dispatchCount() - between;
    stream.submit();
    EXPECT_TRUE(allClose(y, expectedY, {1e-4, 1e-4})) << "forward";
    EXPECT_TRUE(allClose(sum, expectedSum, {1e-4, 1e-4})) << "forward plus an addend";
    EXPECT_TRUE(allClose(dw, expectedDw, {1e-4, 1e-4})) << "weight gradient";
    // From the forward's kept normalised, activated, padded input (ops::PaddedInput): the same bits, no copy.
    EXPECT_EQ(dwFromKept.download(), dw.download()) << "weight gradient from the kept padding";
    EXPECT_EQ(fromKept + 1, padsAgain) << "the weight gradient padded x again";
  }
}

// The one op gives the output of the norm-then-SiLU op followed by the convolution bit for bit (the padding
// copy evaluates the expression group_norm_apply does), and their gradients to float rounding.
TEST_F(NormSiluConvTest, EqualsTheNormThenTheConvolution) {
  for (const Case& c : kCases) {
    SCOPED_TRACE("x " + toString(c.x) + " w " + toString(c.w));
    const Shape yShape = referenceConvOutputShape(c.x, c.w, c.spec);
    const Tensor upstream = randomTensor(context(), yShape, 8);
    std::vector<std::vector<float>> results[2];
    for (const bool fused : {false, true}) {
      const Var x = variable(randomTensor(context(), c.x, 1, -2, 3), true);
      const Var gamma = variable(randomTensor(context(), {c.x[1]}, 4, 0.5f, 2.5f), true);
      const Var beta = variable(randomTensor(context(), {c.x[1]}, 5), true);
      const Var w = variable(randomTensor(context(), c.w, 2), true);
      const Var b = variable(randomTensor(context(), {c.w[0]}, 3), true);
      const Var addend = variable(randomTensor(context(), yShape, 7), true);
      const ops::ConvParams params{c.spec.stride, c.spec.padding};
      const int groups = static_cast<int>(c.groups);
      Stream stream(context());
      Tape tape(stream);
      Var y;
      if (fused) {
        y = fn::convOfGroupNormSilu(tape, x, gamma, beta, groups, 1e-6f, w, b, params, addend);
      } else {
        const Var h = fn::groupNormSilu(tape, x, gamma, beta, groups, 1e-6f);
        y = c.x.size() == 4 ? fn::conv2d(tape, h, w, b, params, addend) : fn::conv3d(tape, h, w, b, params, addend);
      }
      tape.backward({{y, upstream}});
      stream.submit();
      for (const Var& v : {y}) results[fused].push_back(v->value.download());
      for (const Var& v : {x, gamma, beta, w, b, addend}) results[fused].push_back(v->grad.download());
    }
    EXPECT_EQ(results[0][0], results[1][0]) << "forward";
    for (std::size_t k = 1; k < results[0].size(); ++k)
      EXPECT_TRUE(allClose(std::span<const float>(results[1][k]), std::span<const float>(results[0][k]),
                           Shape{static_cast<int64_t>(results[0][k].size())}, {1e-5, 1e-5}))
          << "gradient " << k;
  }
}

TEST_F(NormSiluConvTest, RefusesPointwiseKernelsAndWrongNormShapes) {
  const Tensor x = randomTensor(context(), {1, 4, 5, 6}, 1);
  const Tensor stats = randomTensor(context(), {2, 2}, 2), gamma = randomTensor(context(), {4}, 3);
  const Tensor beta = randomTensor(context(), {4}, 4), wrongGamma = randomTensor(context(), {3}, 5);
  Stream stream(context());
  const ops::ConvParams padded{1, 1};
  Tensor y(context(), {1, 2, 5, 6});
  // a 1x1 kernel on positions of a multiple of 4 runs unpadded (the pointwise kernel)
  const Tensor aligned = randomTensor(context(), {1, 4, 4, 6}, 8);
  Tensor alignedY(context(), {1, 2, 4, 6});
  EXPECT_THROW(ops::convForwardOfNormSilu(stream, aligned, {&stats, &gamma, &beta, 2},
                                          randomTensor(context(), {2, 4, 1, 1}, 6), nullptr, nullptr, {1, 0}, alignedY),
               Error);
  const Tensor w = randomTensor(context(), {2, 4, 3, 3}, 7);
  EXPECT_THROW(ops::convForwardOfNormSilu(stream, x, {&stats, &wrongGamma, &beta, 2}, w, nullptr, nullptr, padded, y),
               Error);
  EXPECT_THROW(ops::convForwardOfNormSilu(stream, x, {&stats, &gamma, &beta, 3}, w, nullptr, nullptr, padded, y),
               Error);
  ops::convForwardOfNormSilu(stream, x, {&stats, &gamma, &beta, 2}, w, nullptr, nullptr, padded, y);
}

}  // namespace
}  // namespace smokesvd::testing
