#include <gtest/gtest.h>

#include "nets/functional/linear.h"
#include "nets/ops/linear.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class LinearTest : public GpuTest {};

// c[m, n] = sum_k A(m, k) B(k, n), with A read from [M, K] or [K, M] and B from [K, N] or [N, K].
std::vector<double> matmulReference(std::span<const double> a, bool transposeA, std::span<const double> b,
                                    bool transposeB, int64_t M, int64_t N, int64_t K) {
  std::vector<double> c(static_cast<std::size_t>(M * N));
  for (int64_t m = 0; m < M; ++m)
    for (int64_t n = 0; n < N; ++n) {
      double sum = 0;
      for (int64_t k = 0; k < K; ++k)
        sum += a[transposeA ? k * M + m : m * K + k] * b[transposeB ? n * K + k : k * N + n];
      c[m * N + n] = sum;
    }
  return c;
}

// y [rows, out] = x [rows, in] W^T + b
std::vector<double> linearReference(std::span<const double> x, std::span<const double> w, std::span<const double> b,
                                    int64_t rows, int64_t in, int64_t out) {
  std::vector<double> y = matmulReference(x, false, w, true, rows, out, in);
  for (int64_t r = 0; r < rows; ++r)
    for (int64_t o = 0; o < out; ++o) y[r * out + o] += b[o];
  return y;
}

struct MatmulCase {
  int64_t M, N, K;
};

// Every layout with sizes that exercise the vec4 paths (multiples of 4), the scalar paths, the K tail and
// more than one workgroup of rows. With a bias here; the backward kernels below run without one. (Each
// layout and alignment is a pipeline of its own, which costs lavapipe a fraction of a second to build.)
TEST_F(LinearTest, MatmulEveryLayoutMatchesReference) {
  for (const MatmulCase& size : {MatmulCase{9, 13, 11}, MatmulCase{8, 12, 16}, MatmulCase{12, 9, 17},
                                 MatmulCase{1, 1, 1}, MatmulCase{37, 3, 6}}) {
    for (bool transposeA : {false, true}) {
      for (bool transposeB : {false, true}) {
        SCOPED_TRACE(::testing::Message() << "M " << size.M << " N " << size.N << " K " << size.K << " transposeA "
                                          << transposeA << " transposeB " << transposeB);
        std::vector<float> a, b, bias;
        const Shape shapeA = transposeA ? Shape{size.K, size.M} : Shape{size.M, size.K};
        const Shape shapeB = transposeB ? Shape{size.N, size.K} : Shape{size.K, size.N};
        Tensor ta = randomTensor(context(), shapeA, 1, -1, 1, &a);
        Tensor tb = randomTensor(context(), shapeB, 2, -1, 1, &b);
        Tensor tbias = randomTensor(context(), {size.N}, 3, -1, 1, &bias);
        Tensor biased = poisonedTensor(context(), {size.M, size.N});
        Stream stream(context());
        ops::matmul(stream, ta, transposeA, tb, transposeB, &tbias, biased);
        stream.submit();
        std::vector<double> expected =
            matmulReference(toDouble(a), transposeA, toDouble(b), transposeB, size.M, size.N, size.K);
        for (int64_t m = 0; m < size.M; ++m)
          for (int64_t n = 0; n < size.N; ++n) expected[m * size.N + n] += bias[n];
        EXPECT_TRUE(allClose(biased, expected, {1e-5, 1e-5}));
      }
    }
  }
}

TEST_F(LinearTest, ForwardAndBackwardKernelsOnBatchedInput) {
  const int64_t batch = 3, tokens = 5, in = 13, out = 7, rows = batch * tokens;
  std::vector<float> x, w, b, g;
  Tensor tx = randomTensor(context(), {batch, tokens, in}, 1, -1, 1, &x);
  Tensor tw = randomTensor(context(), {out, in}, 2, -1, 1, &w);
  Tensor tb = randomTensor(context(), {out}, 3, -1, 1, &b);
  Tensor tg = randomTensor(context(), {batch, tokens, out}, 4, -1, 1, &g);
  Tensor y = poisonedTensor(context(), {batch, tokens, out});
  Tensor gx = poisonedTensor(context(), tx.shape());
  Tensor gw = poisonedTensor(context(), tw.shape());
  Tensor gb = poisonedTensor(context(), tb.shape());
  Stream stream(context());
  ops::linearForward(stream, tx, tw, &tb, y);
  ops::linearBackwardInput(stream, tg, tw, gx);
  ops::linearBackwardWeight(stream, tg, tx, gw);
  ops::linearBackwardBias(stream, tg, gb);
  stream.submit();

  const std::vector<double> dx = toDouble(x), dw = toDouble(w), dg = toDouble(g);
  EXPECT_TRUE(allClose(y, linearReference(dx, dw, toDouble(b), rows, in, out), {1e-5, 1e-5}));
  EXPECT_TRUE(allClose(gx, matmulReference(dg, false, dw, false, rows, in, out), {1e-5, 1e-5}));
  EXPECT_TRUE(allClose(gw, matmulReference(dg, true, dx, false, out, in, rows), {1e-5, 1e-5}));
  std::vector<double> expectedBias(out, 0.0);
  for (int64_t r = 0; r < rows; ++r)
    for (int64_t o = 0; o < out; ++o) expectedBias[o] += dg[r * out + o];
  EXPECT_TRUE(allClose(gb, expectedBias, {1e-5, 1e-5}));
}

TEST_F(LinearTest, GradientsMatchFiniteDifferences) {
  const int64_t rows = 3, in = 5, out = 4;
  std::vector<float> x, w, b, g;
  Var vx = variable(randomTensor(context(), {rows, in}, 1, -1, 1, &x), true);
  Var vw = variable(randomTensor(context(), {out, in}, 2, -1, 1, &w), true);
  Var vb = variable(randomTensor(context(), {out}, 3, -1, 1, &b), true);
  Tensor upstream = randomTensor(context(), {rows, out}, 4, -1, 1, &g);
  Stream stream(context());
  Tape tape(stream);
  tape.backward({{fn::linear(tape, vx, vw, vb), upstream}});
  stream.submit();

  const std::vector<double> dx = toDouble(x), dw = toDouble(w), db = toDouble(b), dg = toDouble(g);
  const Tolerance tolerance{1e-5, 1e-4};
  EXPECT_TRUE(allClose(vx->grad, numericVjp([&](auto p) { return linearReference(p, dw, db, rows, in, out); }, dx, dg),
                       tolerance));
  EXPECT_TRUE(allClose(vw->grad, numericVjp([&](auto p) { return linearReference(dx, p, db, rows, in, out); }, dw, dg),
                       tolerance));
  EXPECT_TRUE(allClose(vb->grad, numericVjp([&](auto p) { return linearReference(dx, dw, p, rows, in, out); }, db, dg),
                       tolerance));
}

TEST_F(LinearTest, WithoutBiasAndShapeErrors) {
  Var x = variable(randomTensor(context(), {2, 3}, 1), true);
  Var w = variable(randomTensor(context(), {4, 3}, 2), true);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::linear(tape, x, w, nullptr);
  EXPECT_EQ(y->value.shape(), (Shape{2, 4}));
  tape.backward(y);
  stream.submit();
  EXPECT_TRUE(x->grad.defined());
  Var wrong = variable(randomTensor(context(), {4, 5}, 3));
  EXPECT_THROW(fn::linear(tape, x, wrong, nullptr), Error);
}

// The runner's `linear` op, forward and backward, as a user calls it.
TEST(LinearCommand, RunsForwardAndBackward) {
  const std::vector<float> x{1, 2, 3, -1, 0, 2}, w{1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}, b{0.5f, 0, 0, -1}, g{1, 0, 0, 1, 0, 1, 2, 0};
  const OpRun run = runOpCommand("linear",
                                 {{"x", io::NpyArray::fromFloats({2, 3}, x)},
                                  {"w", io::NpyArray::fromFloats({4, 3}, w)},
                                  {"b", io::NpyArray::fromFloats({4}, b)},
                                  {"grad_y", io::NpyArray::fromFloats({2, 4}, g)}},
                                 {"y", "grad_x", "grad_w", "grad_b"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const std::vector<double> dx = toDouble(x), dw = toDouble(w), dg = toDouble(g);
  EXPECT_TRUE(allClose(run.outputs.at("y").floats, linearReference(dx, dw, toDouble(b), 2, 3, 4), {2, 4}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, matmulReference(dg, false, dw, false, 2, 3, 4), {2, 3}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_w").floats, matmulReference(dg, true, dx, false, 4, 3, 2), {4, 3}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_b").floats, std::vector<double>{1, 1, 2, 1}, {4}));
}

}  // namespace
}  // namespace smokesvd::testing
