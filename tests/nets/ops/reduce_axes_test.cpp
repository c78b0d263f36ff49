#include <gtest/gtest.h>

#include <cmath>

#include "nets/functional/reduce_axes.h"
#include "nets/ops/reduce_axes.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class ReduceAxesTest : public GpuTest {};

// scale * sum over `axes` of x, laid out like the kept axes.
std::vector<double> sumReference(std::span<const double> x, const Shape& shape, const std::vector<int>& axes,
                                 double scale = 1.0) {
  const Shape kept = ops::reducedShape(shape, axes, true);
  std::vector<double> y(static_cast<std::size_t>(numElements(kept)), 0.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::size_t rest = i, out = 0, stride = 1;
    for (int axis = static_cast<int>(shape.size()) - 1; axis >= 0; --axis) {
      const std::size_t coordinate = rest % static_cast<std::size_t>(shape[axis]);
      rest /= static_cast<std::size_t>(shape[axis]);
      out += (kept[axis] == 1 ? 0 : coordinate) * stride;
      stride *= static_cast<std::size_t>(kept[axis]);
    }
    y[out] += scale * x[i];
  }
  return y;
}

struct SumCase {
  Shape shape;
  std::vector<int> axes;
};

TEST_F(ReduceAxesTest, SumsMatchReference) {
  // Patterns: reduced runs inner, outer, both sides, two runs in 5D; a single long run split into
  // partial sums (with and without vec4 reads); nothing reduced.
  for (const SumCase& c : {SumCase{{3, 5, 7, 9}, {0, 2, 3}}, SumCase{{3, 5, 7, 9}, {3}}, SumCase{{3, 5, 7, 9}, {1}},
                           SumCase{{2, 3, 5, 7, 9}, {1, 3}}, SumCase{{3, 1, 7, 9}, {0, 1}},
                           SumCase{{1000003}, {0}}, SumCase{{4, 1024}, {1}}, SumCase{{3, 2052}, {0, 1}},
                           SumCase{{1031, 3}, {0}}, SumCase{{5, 7}, {}}}) {
    SCOPED_TRACE(toString(c.shape) + " axes " + ::testing::PrintToString(c.axes));
    std::vector<float> x;
    Tensor tx = randomTensor(context(), c.shape, 7, -1, 1, &x);
    Tensor y = poisonedTensor(context(), ops::reducedShape(c.shape, c.axes, false));
    Stream stream(context());
    ops::reduceAxes(stream, ops::ReduceMap::Identity, tx, nullptr, c.axes, 0.5f, y);
    stream.submit();
    const double count = static_cast<double>(ops::reducedCount(c.shape, c.axes));
    EXPECT_TRUE(allClose(y, sumReference(toDouble(x), c.shape, c.axes, 0.5), {1e-6 * std::sqrt(count) + 1e-6, 1e-5}));
  }
}

TEST_F(ReduceAxesTest, MapsOfTwoInputs) {
  const Shape shape{3, 5, 12};
  const std::vector<int> axes{0, 2};
  std::vector<float> a, b;
  Tensor ta = randomTensor(context(), shape, 1, -1, 1, &a);
  Tensor tb = randomTensor(context(), shape, 2, -1, 1, &b);
  using Map = ops::ReduceMap;
  const std::vector<std::pair<Map, double (*)(double, double)>> maps{
      {Map::Difference, [](double x, double z) { return x - z; }},
      {Map::SquaredDifference, [](double x, double z) { return (x - z) * (x - z); }},
      {Map::AbsoluteDifference, [](double x, double z) { return std::abs(x - z); }},
      {Map::Square, [](double x, double) { return x * x; }}};
  for (const auto& [map, f] : maps) {
    std::vector<double> mapped(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) mapped[i] = f(a[i], b[i]);
    Tensor y = poisonedTensor(context(), {5});
    Stream stream(context());
    ops::reduceAxes(stream, map, ta, &tb, axes, 1.0f, y);
    stream.submit();
    EXPECT_TRUE(allClose(y, sumReference(mapped, shape, axes), {1e-5, 1e-5})) << "map " << static_cast<int>(map);
  }
}

TEST_F(ReduceAxesTest, ShapesAndErrors) {
  EXPECT_EQ(ops::reducedShape({2, 3, 4}, std::vector<int>{0, 2}, true), (Shape{1, 3, 1}));
  EXPECT_EQ(ops::reducedShape({2, 3, 4}, std::vector<int>{0, 2}, false), (Shape{3}));
  EXPECT_EQ(ops::normalizeAxes("sum", std::vector<int>{-1, 0}, {2, 3, 4}), (std::vector<int>{0, 2}));
  EXPECT_THROW(ops::normalizeAxes("sum", std::vector<int>{3}, {2, 3, 4}), Error);
  EXPECT_THROW(ops::normalizeAxes("sum", std::vector<int>{1, -2}, {2, 3, 4}), Error);
  Tensor x = randomTensor(context(), {2, 3, 4, 5, 6}, 1);
  Tensor y(context(), {3, 5});
  Stream stream(context());
  EXPECT_THROW(ops::reduceAxes(stream, ops::ReduceMap::Identity, x, nullptr, std::vector<int>{0, 2, 4}, 1.0f, y),
               Error);
}

TEST_F(ReduceAxesTest, SumAndMeanGradientsMatchFiniteDifferences) {
  const Shape shape{2, 3, 5};
  std::vector<float> x;
  Tensor tx = randomTensor(context(), shape, 3, -1, 1, &x);
  const std::vector<double> dx = toDouble(x);
  for (bool average : {false, true}) {
    for (bool keepdims : {false, true}) {
      for (const std::vector<int>& axes : {std::vector<int>{0, -1}, std::vector<int>{1}, std::vector<int>{}}) {
        SCOPED_TRACE(::testing::Message() << "mean " << average << " keepdims " << keepdims << " axes "
                                          << ::testing::PrintToString(axes));
        Var vx = variable(tx, true);
        Stream stream(context());
        Tape tape(stream);
        Var y = average ? fn::mean(tape, vx, axes, keepdims) : fn::sum(tape, vx, axes, keepdims);
        const std::vector<int> normalized = axes.empty() ? ops::allAxes(3) : ops::normalizeAxes("sum", axes, shape);
        EXPECT_EQ(y->value.shape(), ops::reducedShape(shape, normalized, keepdims));
        std::vector<float> g;
        Tensor upstream = randomTensor(context(), y->value.shape(), 4, -1, 1, &g);
        tape.backward({{y, upstream}});
        stream.submit();
        const double scale = average ? 1.0 / static_cast<double>(ops::reducedCount(shape, normalized)) : 1.0;
        const auto f = [&](std::span<const double> p) { return sumReference(p, shape, normalized, scale); };
        EXPECT_TRUE(allClose(y->value, f(dx), {1e-5, 1e-5}));
        EXPECT_TRUE(allClose(vx->grad, numericVjp(f, dx, toDouble(g)), {1e-6, 1e-5}));
      }
    }
  }
}

// The runner's sum and mean ops, forward and backward, as a user calls them.
TEST(ReduceAxesCommand, SumAndMean) {
  const io::NpyArray x = io::NpyArray::fromFloats({2, 3}, {1, 2, 3, 4, 5, 6});
  const OpRun sum = runOpCommand("sum", {{"x", x}, {"grad_y", io::NpyArray::fromFloats({1, 3}, {1, 2, 3})}},
                                 {"y", "grad_x"}, {"axes=0", "keepdims=1"});
  ASSERT_EQ(sum.exitCode, 0) << sum.err;
  EXPECT_EQ(sum.outputs.at("y").shape, (Shape{1, 3}));
  EXPECT_EQ(sum.outputs.at("y").floats, (std::vector<float>{5, 7, 9}));
  EXPECT_EQ(sum.outputs.at("grad_x").floats, (std::vector<float>{1, 2, 3, 1, 2, 3}));
  const OpRun mean = runOpCommand("mean", {{"x", x}}, {"y"});
  ASSERT_EQ(mean.exitCode, 0) << mean.err;
  EXPECT_EQ(mean.outputs.at("y").shape, (Shape{}));
  EXPECT_EQ(mean.outputs.at("y").floats, (std::vector<float>{3.5f}));
}

}  // namespace
}  // namespace smokesvd::testing
