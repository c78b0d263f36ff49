#include <gtest/gtest.h>

#include "nets/functional/concat.h"
#include "nets/ops/concat.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class ConcatTest : public GpuTest {};

int64_t spatialSize(const Shape& shape) { return numElements(shape) / (shape[0] * shape[1]); }

std::vector<double> concatReference(const std::vector<std::vector<double>>& inputs, const std::vector<Shape>& shapes) {
  const int64_t samples = shapes[0][0], s = spatialSize(shapes[0]);
  std::vector<double> y;
  for (int64_t n = 0; n < samples; ++n)
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      const int64_t run = shapes[k][1] * s;
      y.insert(y.end(), inputs[k].begin() + n * run, inputs[k].begin() + (n + 1) * run);
    }
  return y;
}

std::vector<double> sliceReference(std::span<const double> x, const Shape& shape, int64_t begin, int64_t end) {
  const int64_t s = spatialSize(shape);
  std::vector<double> y;
  for (int64_t n = 0; n < shape[0]; ++n)
    y.insert(y.end(), x.begin() + (n * shape[1] + begin) * s, x.begin() + (n * shape[1] + end) * s);
  return y;
}

TEST_F(ConcatTest, ConcatAndSliceMatchReference) {
  // Odd spatial sizes (scalar copies), 4-aligned ones (vec4 copies), 5D, and channel-only tensors.
  for (const std::vector<Shape>& shapes :
       {std::vector<Shape>{{3, 2, 5, 7}, {3, 3, 5, 7}, {3, 1, 5, 7}}, std::vector<Shape>{{2, 4, 4, 4}, {2, 8, 4, 4}},
        std::vector<Shape>{{2, 1, 3, 5, 7}, {2, 4, 3, 5, 7}}, std::vector<Shape>{{5, 3}, {5, 2}}}) {
    SCOPED_TRACE(toString(shapes[0]) + " and " + toString(shapes[1]));
    std::vector<Tensor> tensors;
    std::vector<std::vector<double>> values;
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      std::vector<float> v;
      tensors.push_back(randomTensor(context(), shapes[k], k + 1, -1, 1, &v));
      values.push_back(toDouble(v));
    }
    const Shape out = ops::concatShape(shapes);
    Tensor y = poisonedTensor(context(), out);
    const int64_t begin = 1, end = out[1] - 1;
    Shape sliceShape = out;
    sliceShape[1] = end - begin;
    Tensor slice = poisonedTensor(context(), sliceShape);
    Stream stream(context());
    ops::concatChannels(stream, tensors, y);
    ops::sliceChannels(stream, y, begin, end, slice);
    stream.submit();
    const std::vector<double> expected = concatReference(values, shapes);
    EXPECT_TRUE(allClose(y, expected, {0, 0}));
    EXPECT_TRUE(allClose(slice, sliceReference(expected, out, begin, end), {0, 0}));
  }
}

TEST_F(ConcatTest, GradientsMatchFiniteDifferences) {
  const std::vector<Shape> shapes{{2, 2, 3}, {2, 1, 3}};
  std::vector<float> a, b, g, h;
  Var va = variable(randomTensor(context(), shapes[0], 1, -1, 1, &a), true);
  Var vb = variable(randomTensor(context(), shapes[1], 2, -1, 1, &b), true);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::concatChannels(tape, {va, vb});
  Var s = fn::sliceChannels(tape, y, 1, 3);
  Tensor upstreamY = randomTensor(context(), y->value.shape(), 3, -1, 1, &g);
  Tensor upstreamS = randomTensor(context(), s->value.shape(), 4, -1, 1, &h);
  tape.backward({{y, upstreamY}, {s, upstreamS}});
  stream.submit();

  // f(a, b) = (cat(a, b), cat(a, b)[:, 1:3]), paired with upstream (g, h).
  const std::vector<double> da = toDouble(a), db = toDouble(b);
  std::vector<double> upstream = toDouble(g);
  const std::vector<double> dh = toDouble(h);
  upstream.insert(upstream.end(), dh.begin(), dh.end());
  const auto f = [&](std::span<const double> pa, std::span<const double> pb) {
    std::vector<double> out = concatReference({{pa.begin(), pa.end()}, {pb.begin(), pb.end()}}, shapes);
    const std::vector<double> sliced = sliceReference(out, {2, 3, 3}, 1, 3);
    out.insert(out.end(), sliced.begin(), sliced.end());
    return out;
  };
  EXPECT_TRUE(allClose(va->grad, numericVjp([&](auto p) { return f(p, db); }, da, upstream), {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(vb->grad, numericVjp([&](auto p) { return f(da, p); }, db, upstream), {1e-6, 1e-6}));
}

// sliceBatch: items [begin, end) of the first axis, on odd shapes, every element against a plain copy; its
// gradient against finite differences.
TEST_F(ConcatTest, SliceBatchMatchesReferenceAndFiniteDifferences) {
  for (const Shape& shape : {Shape{5, 1, 3, 7}, Shape{4, 3, 5}, Shape{7, 2}}) {
    SCOPED_TRACE(toString(shape));
    std::vector<float> x, g;
    Var vx = variable(randomTensor(context(), shape, 11, -1, 1, &x), true);
    Stream stream(context());
    Tape tape(stream);
    const int64_t begin = 1, end = shape[0] - 1, item = numElements(shape) / shape[0];
    Var y = fn::sliceBatch(tape, vx, begin, end);
    Shape expectedShape = shape;
    expectedShape[0] = end - begin;
    ASSERT_EQ(y->value.shape(), expectedShape);
    Tensor upstream = randomTensor(context(), expectedShape, 12, -1, 1, &g);
    tape.backward({{y, upstream}});
    stream.submit();
    const std::vector<double> dx = toDouble(x);
    const auto f = [&](std::span<const double> p) {
      return std::vector<double>(p.begin() + begin * item, p.begin() + end * item);
    };
    EXPECT_TRUE(allClose(y->value, f(dx), {0, 0}));
    EXPECT_TRUE(allClose(vx->grad, numericVjp(f, dx, toDouble(g)), {1e-6, 1e-6}));
  }
}

TEST_F(ConcatTest, ShapeErrors) {
  EXPECT_THROW(ops::concatShape(std::vector<Shape>{{2, 3, 4}, {2, 3, 5}}), Error);
  EXPECT_THROW(ops::concatShape(std::vector<Shape>{{3}}), Error);
  Var x = variable(randomTensor(context(), {2, 3, 4}, 1));
  Stream stream(context());
  Tape tape(stream);
  EXPECT_THROW(fn::sliceChannels(tape, x, 2, 4), Error);
  EXPECT_THROW(fn::sliceChannels(tape, x, 2, 1), Error);
  EXPECT_EQ(fn::sliceChannels(tape, x, 1, 1)->value.shape(), (Shape{2, 0, 4}));
}

// The runner's concat and slice ops, forward and backward, as a user calls them.
TEST(ConcatCommand, ConcatAndSlice) {
  const io::NpyArray a = io::NpyArray::fromFloats({2, 1, 2}, {1, 2, 3, 4});
  const io::NpyArray b = io::NpyArray::fromFloats({2, 2, 2}, {5, 6, 7, 8, 9, 10, 11, 12});
  const io::NpyArray c = io::NpyArray::fromFloats({2, 1, 2}, {13, 14, 15, 16});
  const io::NpyArray g = io::NpyArray::fromFloats({2, 4, 2}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15});
  const OpRun concat = runOpCommand("concat_channels", {{"a", a}, {"b", b}, {"c", c}, {"grad_y", g}}, {"y", "grad_b"});
  ASSERT_EQ(concat.exitCode, 0) << concat.err;
  EXPECT_EQ(concat.outputs.at("y").shape, (Shape{2, 4, 2}));
  EXPECT_EQ(concat.outputs.at("y").floats, (std::vector<float>{1, 2, 5, 6, 7, 8, 13, 14, 3, 4, 9, 10, 11, 12, 15, 16}));
  EXPECT_EQ(concat.outputs.at("grad_b").floats, (std::vector<float>{2, 3, 4, 5, 10, 11, 12, 13}));

  const OpRun slice = runOpCommand("slice_channels", {{"x", b}, {"grad_y", a}}, {"y", "grad_x"}, {"begin=1", "end=2"});
  ASSERT_EQ(slice.exitCode, 0) << slice.err;
  EXPECT_EQ(slice.outputs.at("y").floats, (std::vector<float>{7, 8, 11, 12}));
  EXPECT_EQ(slice.outputs.at("grad_x").floats, (std::vector<float>{0, 0, 1, 2, 0, 0, 3, 4}));
}

}  // namespace
}  // namespace smokesvd::testing
