#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "nets/functional/pool.h"
#include "nets/io/npy.h"
#include "nets/ops/pool.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using ops::PoolKind;

class PoolTest : public GpuTest {};

// (N, C, D, H, W) of a 4D or 5D shape, D = 1 for 4D.
std::array<int64_t, 5> dims5(const Shape& s) {
  return s.size() == 5 ? std::array<int64_t, 5>{s[0], s[1], s[2], s[3], s[4]}
                       : std::array<int64_t, 5>{s[0], s[1], 1, s[2], s[3]};
}

// PyTorch's pooling with kernel 2, stride 2, ceil_mode=True written out: the window of output (z, y, x)
// is [2z, min(2z + kd, D)) x [2y, min(2y + 2, H)) x [2x, min(2x + 2, W)), kd = 2 in 3D and 1 in 2D.
std::vector<double> reference(PoolKind kind, std::span<const double> x, const Shape& shape) {
  const auto [n, c, d, h, w] = dims5(shape);
  const int64_t kd = shape.size() == 5 ? 2 : 1;
  const int64_t od = (d + kd - 1) / kd, oh = (h + 1) / 2, ow = (w + 1) / 2;
  std::vector<double> y;
  for (int64_t plane = 0; plane < n * c; ++plane)
    for (int64_t z = 0; z < od; ++z)
      for (int64_t yy = 0; yy < oh; ++yy)
        for (int64_t xx = 0; xx < ow; ++xx) {
          double best = -INFINITY, sum = 0;
          int count = 0;
          for (int64_t iz = kd * z; iz < std::min(kd * z + kd, d); ++iz)
            for (int64_t iy = 2 * yy; iy < std::min(2 * yy + 2, h); ++iy)
              for (int64_t ix = 2 * xx; ix < std::min(2 * xx + 2, w); ++ix) {
                const double v = x[static_cast<std::size_t>(((plane * d + iz) * h + iy) * w + ix)];
                best = std::max(best, v);
                sum += v;
                ++count;
              }
          y.push_back(kind == PoolKind::Max ? best : sum / count);
        }
  return y;
}

TEST_F(PoolTest, ForwardMatchesReferenceOnOddShapes) {
  // widths that are multiples of 8 take the vec4 path, the others the per-element path
  for (const Shape& shape : {Shape{2, 3, 7, 9}, Shape{1, 2, 8, 5}, Shape{1, 1, 1, 1}, Shape{2, 2, 5, 7, 9},
                             Shape{1, 3, 4, 3, 6}, Shape{1, 1, 1, 3, 2}, Shape{2, 1, 5, 24}, Shape{1, 2, 3, 5, 40}}) {
    for (PoolKind kind : {PoolKind::Max, PoolKind::Average}) {
      SCOPED_TRACE(toString(shape) + (kind == PoolKind::Max ? " max" : " average"));
      std::vector<float> x;
      const Tensor input = randomTensor(context(), shape, 1, -1, 1, &x);
      Tensor y = poisonedTensor(context(), ops::pooledShape(shape));
      Stream stream(context());
      ops::poolForward(stream, kind, input, y);
      stream.submit();
      EXPECT_TRUE(allClose(y, reference(kind, toDouble(x), shape), {1e-6, 1e-6}));
    }
  }
}

TEST_F(PoolTest, BackwardMatchesFiniteDifferences) {
  // random values are distinct, so no max-pool window has a tie (a kink of the max)
  for (const Shape& shape : {Shape{2, 2, 5, 7}, Shape{1, 2, 3, 5, 4}, Shape{1, 2, 3, 8}, Shape{1, 1, 3, 3, 16}}) {
    for (PoolKind kind : {PoolKind::Max, PoolKind::Average}) {
      SCOPED_TRACE(toString(shape) + (kind == PoolKind::Max ? " max" : " average"));
      std::vector<float> x, g;
      const Tensor input = randomTensor(context(), shape, 2, -1, 1, &x);
      const Tensor gy = randomTensor(context(), ops::pooledShape(shape), 3, -1, 1, &g);
      Tensor gx = poisonedTensor(context(), shape);
      Stream stream(context());
      ops::poolBackward(stream, kind, input, gy, gx);
      stream.submit();
      const auto expected = numericVjp([&](std::span<const double> p) { return reference(kind, p, shape); },
                                       toDouble(x), toDouble(g));
      EXPECT_TRUE(allClose(gx, expected, {1e-5, 1e-5}));
    }
  }
}

TEST_F(PoolTest, AutogradWrappersChainWithTheTape) {
  // max-pool then average-pool of the result: gradients flow through both wrappers
  const Shape shape{1, 2, 7, 6};
  std::vector<float> x, g;
  Var vx = variable(randomTensor(context(), shape, 6, -1, 1, &x), true);
  const Shape out = ops::pooledShape(ops::pooledShape(shape));
  const Tensor upstream = randomTensor(context(), out, 7, -1, 1, &g);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::avgPool(tape, fn::maxPool(tape, vx));
  tape.backward({{y, upstream}});
  stream.submit();
  auto composed = [&](std::span<const double> p) {
    return reference(PoolKind::Average, reference(PoolKind::Max, p, shape), ops::pooledShape(shape));
  };
  EXPECT_TRUE(allClose(y->value, composed(toDouble(x)), {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(vx->grad, numericVjp(composed, toDouble(x), toDouble(g)), {1e-5, 1e-5}));
}

TEST_F(PoolTest, MaxPoolRoutesTiesToTheFirstMaximumAndWritesEveryGradient) {
  // [1, 1, 3, 3]: windows {0,1,3,4}, {2,5}, {6,7}, {8}; ties at 1 and 3 (value 5), at 6 and 7 (value 2)
  const std::vector<float> x{1, 5, 0, 5, 4, 0, 2, 2, -3};
  const Tensor input = Tensor::fromHost(context(), {1, 1, 3, 3}, x);
  const Tensor gy = Tensor::fromHost(context(), {1, 1, 2, 2}, std::vector<float>{10, 20, 30, 40});
  Tensor y = poisonedTensor(context(), {1, 1, 2, 2});
  Tensor gx = poisonedTensor(context(), {1, 1, 3, 3});
  Stream stream(context());
  ops::poolForward(stream, PoolKind::Max, input, y);
  ops::poolBackward(stream, PoolKind::Max, input, gy, gx);
  stream.submit();
  EXPECT_TRUE(allClose(y, std::vector<double>{5, 0, 2, -3}, {0, 0}));
  EXPECT_TRUE(allClose(gx, std::vector<double>{0, 10, 20, 0, 0, 0, 30, 0, 40}, {0, 0}));
}

TEST_F(PoolTest, MaxPoolTiesOnTheVec4PathFollowScanOrder) {
  // [1, 1, 2, 2, 8]: four 2x2x2 windows, each holding its maximum 7 twice
  std::vector<float> x(32, 0.0f);
  auto at = [](int z, int y, int xx) { return static_cast<std::size_t>((z * 2 + y) * 8 + xx); };
  x[at(0, 1, 1)] = 7, x[at(1, 0, 0)] = 7;  // window 0: (z0, y1, x1) comes first
  x[at(1, 0, 2)] = 7, x[at(1, 1, 3)] = 7;  // window 1: (z1, y0, x0) first
  x[at(0, 0, 5)] = 7, x[at(0, 1, 4)] = 7;  // window 2: (z0, y0, x1) first
  x[at(0, 0, 6)] = 7, x[at(0, 0, 7)] = 7;  // window 3: (z0, y0, x0) first
  const Tensor input = Tensor::fromHost(context(), {1, 1, 2, 2, 8}, x);
  const Tensor gy = Tensor::fromHost(context(), {1, 1, 1, 1, 4}, std::vector<float>{1, 2, 3, 4});
  Tensor gx = poisonedTensor(context(), {1, 1, 2, 2, 8});
  Stream stream(context());
  ops::poolBackward(stream, PoolKind::Max, input, gy, gx);
  stream.submit();
  std::vector<double> expected(32, 0.0);
  expected[at(0, 1, 1)] = 1, expected[at(1, 0, 2)] = 2, expected[at(0, 0, 5)] = 3, expected[at(0, 0, 6)] = 4;
  EXPECT_TRUE(allClose(gx, expected, {0, 0}));
}

TEST_F(PoolTest, RunsThroughSmokesvdOp) {
  const Shape shape{1, 2, 3, 5, 3};
  const Shape pooled = ops::pooledShape(shape);
  const std::vector<float> x = randomValues(90, 4), g = randomValues(static_cast<std::size_t>(numElements(pooled)), 5);
  for (const auto& [op, kind] : {std::pair{"max_pool", PoolKind::Max}, std::pair{"avg_pool", PoolKind::Average}}) {
    SCOPED_TRACE(op);
    const OpRun run = runOpCommand(
        op, {{"x", io::NpyArray::fromFloats(shape, x)}, {"grad_y", io::NpyArray::fromFloats(pooled, g)}}, {"y", "grad_x"});
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(allClose(run.outputs.at("y").floats, reference(kind, toDouble(x), shape), pooled, {1e-6, 1e-6}));
    const auto expected = numericVjp([&, kind = kind](std::span<const double> p) { return reference(kind, p, shape); },
                                     toDouble(x), toDouble(g));
    EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, expected, shape, {1e-5, 1e-5}));
  }
}

}  // namespace
}  // namespace smokesvd::testing
