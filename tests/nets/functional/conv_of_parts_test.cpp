// fn::convOfParts against what it stands for, conv(cat(parts)) sliced to the output group: the same
// output and the same gradients for every input (the op driver test checks it against central
// differences and through `smokesvd op`).
#include <gtest/gtest.h>

#include "nets/functional/concat.h"
#include "nets/functional/conv.h"
#include "nets/functional/conv_of_parts.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class ConvOfPartsTest : public GpuTest {};

TEST_F(ConvOfPartsTest, EqualsTheSlicedConvolutionOfTheConcatenationWithItsGradients) {
  const ops::ConvParams params{1, 1};
  const Shape partShapes[] = {{2, 3, 3, 4, 5}, {2, 1, 3, 4, 5}, {2, 2, 3, 4, 5}};
  const int64_t outBegin = 2, outEnd = 7;
  const Shape yShape{2, outEnd - outBegin, 3, 4, 5};
  Tensor upstream = randomTensor(context(), yShape, 9);

  // Two copies of each input, one per path, so that their gradients can be compared.
  auto inputs = [&](std::vector<Var>& parts, Var& w, Var& b) {
    uint64_t seed = 1;
    for (const Shape& shape : partShapes) parts.push_back(variable(randomTensor(context(), shape, seed++), true));
    w = variable(randomTensor(context(), {9, 6, 3, 3, 3}, 7), true);
    b = variable(randomTensor(context(), {9}, 8), true);
  };
  std::vector<Var> parts, joinedParts;
  Var w, b, joinedW, joinedB;
  inputs(parts, w, b);
  inputs(joinedParts, joinedW, joinedB);

  Stream stream(context());
  Tape tape(stream);
  const Var y = fn::convOfParts(tape, parts, w, b, params, outBegin, outEnd);
  const Var joined = fn::sliceChannels(
      tape, fn::conv3d(tape, fn::concatChannels(tape, joinedParts), joinedW, joinedB, params), outBegin, outEnd);
  tape.backward({{y, upstream}, {joined, upstream}});
  stream.submit();

  ASSERT_EQ(y->value.shape(), yShape);
  const Tolerance tolerance{1e-5, 1e-5};
  EXPECT_TRUE(allClose(y->value, joined->value.download(), tolerance));
  for (std::size_t i = 0; i < parts.size(); ++i)
    EXPECT_TRUE(allClose(parts[i]->grad, joinedParts[i]->grad.download(), tolerance)) << "part " << i;
  EXPECT_TRUE(allClose(w->grad, joinedW->grad.download(), tolerance));
  EXPECT_TRUE(allClose(b->grad, joinedB->grad.download(), tolerance));
}

TEST_F(ConvOfPartsTest, RefusesPartsThatDoNotMatchTheWeight) {
  Stream stream(context());
  Tape tape(stream);
  const Var a = variable(randomTensor(context(), {1, 2, 3, 3}, 1));
  const Var b = variable(randomTensor(context(), {1, 2, 3, 3}, 2));
  const Var w = variable(randomTensor(context(), {3, 5, 1, 1}, 3));
  EXPECT_THROW(fn::convOfParts(tape, {a, b}, w, nullptr, {}, 0, 3), Error);  // 4 channels, the weight wants 5
  const Var w4 = variable(randomTensor(context(), {3, 4, 1, 1}, 4));
  EXPECT_THROW(fn::convOfParts(tape, {a, b}, w4, nullptr, {}, 2, 4), Error);  // past the 3 output channels
  EXPECT_THROW(fn::convOfParts(tape, {a, variable(randomTensor(context(), {1, 2, 4, 3}, 5))}, w4, nullptr, {}, 0, 3),
               Error);  // parts of different sizes
}

}  // namespace
}  // namespace smokesvd::testing
