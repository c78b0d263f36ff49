// The autograd wrappers and op registrations of the convolutions: forward and every gradient the tape
// produces equal what the raw kernels give for the same upstream gradient.
#include <gtest/gtest.h>

#include <ostream>

#include "nets/functional/conv.h"
#include "nets/ops/elementwise.h"
#include "nets/op_registry.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using ConvFunction = Var (*)(Tape&, const Var&, const Var&, const Var&, const ops::ConvParams&);

// The convolutions without an addend.
Var conv2dOf(Tape& t, const Var& x, const Var& w, const Var& b, const ops::ConvParams& p) {
  return fn::conv2d(t, x, w, b, p);
}
Var conv3dOf(Tape& t, const Var& x, const Var& w, const Var& b, const ops::ConvParams& p) {
  return fn::conv3d(t, x, w, b, p);
}

struct WrapperCase {
  const char* op;
  ConvFunction function;
  bool transposed;
  Shape x;
  Shape w;
  ops::ConvParams params;
};

void PrintTo(const WrapperCase& c, std::ostream* os) { *os << c.op; }

class ConvFunctionalTest : public GpuTest, public ::testing::WithParamInterface<WrapperCase> {};

std::vector<float> values(const Tensor& t) { return t.download(); }

TEST_P(ConvFunctionalTest, TapeGradientsEqualRawKernels) {
  const WrapperCase& c = GetParam();
  const int64_t outChannels = c.transposed ? c.w[1] : c.w[0];
  Var x = variable(randomTensor(context(), c.x, 1), true, "x");
  Var w = variable(randomTensor(context(), c.w, 2), true, "w");
  Var b = variable(randomTensor(context(), {outChannels}, 3), true, "b");
  const Shape yShape = c.transposed ? ops::convTransposeOutputShape(c.x, c.w, c.params)
                                    : ops::convOutputShape(c.x, c.w, c.params);
  Tensor upstream = randomTensor(context(), yShape, 4);

  Stream stream(context());
  Tape tape(stream);
  Var y = c.function(tape, x, w, b, c.params);
  tape.backward({{y, upstream}});
  Tensor rawY = poisonedTensor(context(), yShape), rawDx = poisonedTensor(context(), c.x);
  Tensor rawDw = poisonedTensor(context(), c.w), rawDb = poisonedTensor(context(), {outChannels});
  if (c.transposed) {
    ops::convTransposeForward(stream, x->value, w->value, &b->value, c.params, rawY);
    ops::convTransposeBackwardInput(stream, upstream, w->value, c.params, rawDx);
    ops::convTransposeBackwardWeight(stream, x->value, upstream, c.params, rawDw);
  } else {
    ops::convForward(stream, x->value, w->value, &b->value, c.params, rawY);
    ops::convBackwardInput(stream, upstream, w->value, c.params, rawDx);
    ops::convBackwardWeight(stream, x->value, upstream, c.params, rawDw);
  }
  ops::convBackwardBias(stream, upstream, rawDb);
  stream.submit();

  EXPECT_TRUE(allClose(y->value, values(rawY), {0, 0})) << c.op;
  EXPECT_TRUE(allClose(x->grad, values(rawDx), {0, 0})) << c.op;
  EXPECT_TRUE(allClose(w->grad, values(rawDw), {0, 0})) << c.op;
  EXPECT_TRUE(allClose(b->grad, values(rawDb), {0, 0})) << c.op;
}

TEST_P(ConvFunctionalTest, RegisteredOpRunsTheWrapper) {
  const WrapperCase& c = GetParam();
  const OpSpec& spec = findOp(c.op);
  EXPECT_EQ(spec.inputs, (std::vector<std::string>{"x", "w"}));
  const std::vector<std::string> optional = c.transposed ? std::vector<std::string>{"b"}
                                                         : std::vector<std::string>{"b", "addend"};
  EXPECT_EQ(spec.optionalInputs, optional);
  std::map<std::string, std::string> attrs{{"stride", std::to_string(c.params.stride)},
                                           {"padding", std::to_string(c.params.padding)}};
  if (c.transposed) attrs["output_padding"] = std::to_string(c.params.outputPadding);
  Var x = variable(randomTensor(context(), c.x, 1), true);
  Var w = variable(randomTensor(context(), c.w, 2), true);
  Stream stream(context());
  Tape tape(stream);
  const std::vector<Var> outputs = spec.apply(tape, {x, w, nullptr}, resolveAttrs(spec, attrs));
  Var direct = c.function(tape, x, w, nullptr, c.params);
  stream.submit();
  ASSERT_EQ(outputs.size(), 1u);
  EXPECT_TRUE(allClose(outputs[0]->value, values(direct->value), {0, 0}));
}

// As in a bottleneck block: x read by a 3x3x3 convolution and a pointwise one, both through leaky ReLU, the first's
// output added in the second's writes. x's gradient is the sum of the two convolutions' input gradients, the
// second added as its kernel writes it (Tape::accumulateWriting): equal to the raw kernels' sum, bit for bit.
class ConvFunctionalSumTest : public GpuTest {};

TEST_F(ConvFunctionalSumTest, AnInputOfTwoConvolutionsGetsTheSumOfTheirGradients) {
  Context& context = this->context();
  const Shape xShape{1, 3, 4, 5, 6}, yShape{1, 4, 4, 5, 6};
  Var x = variable(randomTensor(context, xShape, 21), true, "x");
  Var w1 = variable(randomTensor(context, {4, 3, 3, 3, 3}, 22), true, "w1");
  Var w2 = variable(randomTensor(context, {4, 3, 1, 1, 1}, 23), true, "w2");
  Tensor upstream = randomTensor(context, yShape, 24);
  ops::ConvParams p1{.padding = 1, .inputSlope = 0.2f}, p2{.inputSlope = 0.2f};

  Stream stream(context);
  Tape tape(stream);
  Var y1 = fn::conv3d(tape, x, w1, nullptr, p1);
  Var y2 = fn::conv3d(tape, x, w2, nullptr, p2, y1);
  tape.backward({{y2, upstream}});
  Tensor dx1(context, xShape), dx2(context, xShape), expected = poisonedTensor(context, xShape);
  ops::convBackwardActivatedInput(stream, upstream, w1->value, x->value, p1, dx1);
  ops::convBackwardActivatedInput(stream, upstream, w2->value, x->value, p2, dx2);
  ops::add(stream, dx2, dx1, expected);
  stream.submit();
  EXPECT_TRUE(allClose(x->grad, values(expected), {0, 0}));
}

INSTANTIATE_TEST_SUITE_P(
    Wrappers, ConvFunctionalTest,
    ::testing::Values(WrapperCase{"conv2d", conv2dOf, false, {2, 3, 7, 9}, {5, 3, 3, 3}, {2, 1}},
                      WrapperCase{"conv3d", conv3dOf, false, {1, 3, 5, 6, 7}, {4, 3, 3, 3, 3}, {1, 1}},
                      WrapperCase{"conv_transpose2d", fn::convTranspose2d, true, {2, 3, 4, 5}, {3, 5, 3, 3}, {2, 1, 1}},
                      WrapperCase{"conv_transpose3d", fn::convTranspose3d, true, {1, 4, 3, 4, 3}, {4, 3, 2, 2, 2}, {2, 0}}),
    [](const ::testing::TestParamInfo<WrapperCase>& param) { return std::string(param.param.op); });

}  // namespace
}  // namespace smokesvd::testing
