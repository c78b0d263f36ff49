#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "nets/functional/resample.h"
#include "nets/io/npy.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using ops::Resample;
using ops::ResampleMode;

class ResampleTest : public GpuTest {};

struct AxisStencil {
  int64_t i0, i1;
  double w1;  // weight of i1; i0 gets 1 - w1
};

// PyTorch's upsample_{nearest,bilinear2d,trilinear3d} (align_corners=False) along one axis, with its
// scale = 1 / scale_factor: nearest src = floor(o * scale) computed in float; linear
// src = max(scale (o + 0.5) - 0.5, 0), i1 = i0 + 1 unless i0 is the last index.
AxisStencil axisStencil(const Resample& r, int64_t o, int64_t in) {
  const double scale = r.down ? r.factor : 1.0 / r.factor;
  if (r.mode == ResampleMode::Nearest) {
    const float source = std::floor(static_cast<float>(o) * static_cast<float>(scale));
    const int64_t i = std::min<int64_t>(static_cast<int64_t>(source), in - 1);
    return {i, i, 0.0};
  }
  const double src = std::max(scale * (static_cast<double>(o) + 0.5) - 0.5, 0.0);
  const int64_t i0 = static_cast<int64_t>(src);
  return {i0, i0 < in - 1 ? i0 + 1 : i0, src - static_cast<double>(i0)};
}

std::vector<double> reference(const Resample& r, std::span<const double> x, const Shape& shape) {
  const bool volume = shape.size() == 5;
  const int64_t planes = shape[0] * shape[1];
  const int64_t d = volume ? shape[2] : 1, h = shape[shape.size() - 2], w = shape.back();
  const Shape outShape = ops::resampledShape(shape, r);
  const int64_t od = volume ? outShape[2] : 1, oh = outShape[outShape.size() - 2], ow = outShape.back();
  std::vector<double> y;
  for (int64_t p = 0; p < planes; ++p)
    for (int64_t oz = 0; oz < od; ++oz)
      for (int64_t oy = 0; oy < oh; ++oy)
        for (int64_t ox = 0; ox < ow; ++ox) {
          const AxisStencil sz = volume ? axisStencil(r, oz, d) : AxisStencil{oz, oz, 0.0};
          const AxisStencil sy = axisStencil(r, oy, h), sx = axisStencil(r, ox, w);
          double value = 0;
          for (int corner = 0; corner < 8; ++corner) {
            const bool uz = corner & 4, uy = corner & 2, ux = corner & 1;
            const double weight = (uz ? sz.w1 : 1 - sz.w1) * (uy ? sy.w1 : 1 - sy.w1) * (ux ? sx.w1 : 1 - sx.w1);
            const int64_t iz = uz ? sz.i1 : sz.i0, iy = uy ? sy.i1 : sy.i0, ix = ux ? sx.i1 : sx.i0;
            value += weight * x[static_cast<std::size_t>(((p * d + iz) * h + iy) * w + ix)];
          }
          y.push_back(value);
        }
  return y;
}

std::string describe(const Resample& r, const Shape& shape) {
  return std::string(r.mode == ResampleMode::Nearest ? "nearest " : "linear ") + (r.down ? "down " : "up ") +
         std::to_string(r.factor) + " " + toString(shape);
}

std::vector<Resample> allResamples(std::initializer_list<int> factors) {
  std::vector<Resample> all;
  for (ResampleMode mode : {ResampleMode::Nearest, ResampleMode::Linear})
    for (bool down : {false, true})
      for (int factor : factors) all.push_back({mode, down, factor});
  return all;
}

TEST_F(ResampleTest, ForwardMatchesPyTorchSemanticsOnOddShapes) {
  // odd widths take the scalar paths, widths and planes that are multiples of 4 the vec4 paths
  for (const Shape& shape : {Shape{2, 3, 7, 9}, Shape{1, 2, 5, 9, 7}, Shape{1, 2, 5, 8}, Shape{2, 1, 4, 5, 12}})
    for (const Resample& r : allResamples({2, 3, 4})) {
      SCOPED_TRACE(describe(r, shape));
      std::vector<float> x;
      const Tensor input = randomTensor(context(), shape, 1, -1, 1, &x);
      Tensor y = poisonedTensor(context(), ops::resampledShape(shape, r));
      Stream stream(context());
      ops::resampleForward(stream, r, input, y);
      stream.submit();
      EXPECT_TRUE(allClose(y, reference(r, toDouble(x), shape), {1e-6, 1e-6}));
    }
}

TEST_F(ResampleTest, KnownValuesOfLinearResampling) {
  // x2 up samples at -0.25 (clamped to 0), 0.25, 0.75, 1.25, ...; down by 2 averages pairs (of columns,
  // and of the two equal rows), down by 3 takes the middle element
  const Tensor x = Tensor::fromHost(context(), {1, 1, 1, 4}, std::vector<float>{0, 4, 8, 12});
  const std::vector<float> row6{0, 1, 2, 3, 4, 5};
  std::vector<float> rows6(row6);
  rows6.insert(rows6.end(), row6.begin(), row6.end());
  rows6.insert(rows6.end(), row6.begin(), row6.end());
  const Tensor six = Tensor::fromHost(context(), {1, 1, 3, 6}, rows6);
  Tensor up = poisonedTensor(context(), {1, 1, 2, 8});
  Tensor half = poisonedTensor(context(), {1, 1, 1, 3});
  Tensor third = poisonedTensor(context(), {1, 1, 1, 2});
  Stream stream(context());
  ops::resampleForward(stream, {ResampleMode::Linear, false, 2}, x, up);
  ops::resampleForward(stream, {ResampleMode::Linear, true, 2}, six, half);
  ops::resampleForward(stream, {ResampleMode::Linear, true, 3}, six, third);
  stream.submit();
  const std::vector<double> row{0, 1, 3, 5, 7, 9, 11, 12};
  std::vector<double> rows(row);
  rows.insert(rows.end(), row.begin(), row.end());
  EXPECT_TRUE(allClose(up, rows, {1e-6, 0}));
  EXPECT_TRUE(allClose(half, std::vector<double>{0.5, 2.5, 4.5}, {1e-6, 0}));
  EXPECT_TRUE(allClose(third, std::vector<double>{1, 4}, {1e-6, 0}));
}

TEST_F(ResampleTest, BackwardMatchesFiniteDifferences) {
  // H = 19 and D = 10 span several runs of the row-wise transpose of upsampling (8 inputs each)
  for (const Shape& shape : {Shape{2, 1, 5, 7}, Shape{1, 2, 3, 5, 4}, Shape{1, 1, 3, 8}, Shape{1, 1, 3, 3, 8},
                             Shape{1, 1, 19, 4}, Shape{1, 1, 10, 3, 4}})
    for (const Resample& r : allResamples({2, 3})) {
      SCOPED_TRACE(describe(r, shape));
      std::vector<float> x, g;
      const Shape outShape = ops::resampledShape(shape, r);
      const Tensor gy = randomTensor(context(), outShape, 3, -1, 1, &g);
      x = randomValues(static_cast<std::size_t>(numElements(shape)), 2);
      Tensor gx = poisonedTensor(context(), shape);
      Stream stream(context());
      ops::resampleBackward(stream, r, gy, gx);
      stream.submit();
      const auto expected =
          numericVjp([&](std::span<const double> p) { return reference(r, p, shape); }, toDouble(x), toDouble(g));
      EXPECT_TRUE(allClose(gx, expected, {1e-5, 1e-5}));
    }
}

TEST_F(ResampleTest, AutogradWrappersRoundTrip) {
  // downsample(upsample(x)) through the tape, in 3D with batch 2
  const Shape shape{2, 1, 3, 5, 3};
  std::vector<float> x, g;
  Var vx = variable(randomTensor(context(), shape, 4, -1, 1, &x), true);
  const Tensor upstream = randomTensor(context(), shape, 5, -1, 1, &g);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::downsample(tape, fn::upsample(tape, vx, 2, ResampleMode::Linear), 2, ResampleMode::Nearest);
  tape.backward({{y, upstream}});
  stream.submit();
  const Resample up{ResampleMode::Linear, false, 2}, down{ResampleMode::Nearest, true, 2};
  auto composed = [&](std::span<const double> p) {
    return reference(down, reference(up, p, shape), ops::resampledShape(shape, up));
  };
  EXPECT_TRUE(allClose(y->value, composed(toDouble(x)), {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(vx->grad, numericVjp(composed, toDouble(x), toDouble(g)), {1e-5, 1e-5}));
}

TEST_F(ResampleTest, RunsThroughSmokesvdOp) {
  const Shape shape{1, 2, 3, 5, 4};
  const std::vector<float> x = randomValues(120, 6);
  struct Case {
    std::string op;
    std::vector<std::string> attrs;
    Resample resample;
  };
  const Case cases[] = {{"upsample", {"factor=2", "mode=trilinear"}, {ResampleMode::Linear, false, 2}},
                        {"downsample", {"factor=2", "mode=nearest"}, {ResampleMode::Nearest, true, 2}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.op);
    const Resample r = c.resample;
    const Shape outShape = ops::resampledShape(shape, r);
    const std::vector<float> g = randomValues(static_cast<std::size_t>(numElements(outShape)), 7);
    const OpRun run = runOpCommand(
        c.op, {{"x", io::NpyArray::fromFloats(shape, x)}, {"grad_y", io::NpyArray::fromFloats(outShape, g)}},
        {"y", "grad_x"}, c.attrs);
    ASSERT_EQ(run.exitCode, 0) << run.err;
    EXPECT_TRUE(allClose(run.outputs.at("y").floats, reference(r, toDouble(x), shape), outShape, {1e-6, 1e-6}));
    const auto expected =
        numericVjp([&](std::span<const double> p) { return reference(r, p, shape); }, toDouble(x), toDouble(g));
    EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, expected, shape, {1e-5, 1e-5}));
  }
  const OpRun bad = runOpCommand("upsample", {{"x", io::NpyArray::fromFloats(shape, x)}}, {"y"}, {"mode=cubic"});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("mode='cubic'"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace smokesvd::testing
