#include <gtest/gtest.h>

#include <numeric>

#include "nets/functional/dropout.h"
#include "nets/io/npy.h"
#include "nets/ops/dropout.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class DropoutTest : public GpuTest {};

// The mask of docs/nn-layers.md, written out on the CPU.
uint32_t pcgHash(uint32_t v) {
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

bool keep(uint64_t seed, uint32_t index, float p) {
  const uint32_t key = pcgHash(static_cast<uint32_t>(seed) ^ pcgHash(static_cast<uint32_t>(seed >> 32)));
  const float u = static_cast<float>(pcgHash(index ^ key) >> 8) * (1.0f / 16777216.0f);
  return u >= p;
}

std::vector<double> reference(std::span<const float> x, float p, uint64_t seed) {
  std::vector<double> y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    y[i] = keep(seed, static_cast<uint32_t>(i), p) ? x[i] / (1.0 - p) : 0.0;
  return y;
}

TEST_F(DropoutTest, ForwardAndBackwardApplyTheHashMask) {
  const Shape shape{2, 3, 5, 7};
  const float p = 0.3f;
  const uint64_t seed = 0x123456789abcull;
  std::vector<float> x, g;
  Var vx = variable(randomTensor(context(), shape, 1, -1, 1, &x), true);
  const Tensor upstream = randomTensor(context(), shape, 2, -1, 1, &g);
  Stream stream(context());
  Tape tape(stream);
  Var y = fn::dropout(tape, vx, p, seed, true);
  tape.backward({{y, upstream}});
  stream.submit();
  EXPECT_TRUE(allClose(y->value, reference(x, p, seed), {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(vx->grad, reference(g, p, seed), {1e-6, 1e-6}));
}

TEST_F(DropoutTest, SameSeedSameMaskAndMeanIsPreserved) {
  const int64_t n = 200001;
  const float p = 0.25f;
  const Tensor ones = Tensor::fromHost(context(), {n}, std::vector<float>(n, 1.0f));
  Tensor first = poisonedTensor(context(), {n});
  Tensor again = poisonedTensor(context(), {n});
  Tensor other = poisonedTensor(context(), {n});
  Stream stream(context());
  ops::dropout(stream, ones, p, 7, first);
  ops::dropout(stream, ones, p, 7, again);
  ops::dropout(stream, ones, p, 8, other);
  stream.submit();
  const std::vector<float> a = first.download(), b = again.download(), c = other.download();
  EXPECT_EQ(a, b);
  std::size_t kept = 0, differ = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(a[i] == 0.0f || a[i] == 1.0f / (1.0f - p)) << i << ": " << a[i];
    kept += a[i] != 0.0f;
    differ += (a[i] != 0.0f) != (c[i] != 0.0f);
  }
  // keep rate 0.75: the binomial standard deviation of the kept fraction is about 0.001
  EXPECT_NEAR(static_cast<double>(kept) / n, 1.0 - p, 0.005);
  const double mean = std::accumulate(a.begin(), a.end(), 0.0) / n;
  EXPECT_NEAR(mean, 1.0, 0.01);
  // two independent masks disagree on 2 p (1 - p) = 37.5 % of the elements
  EXPECT_NEAR(static_cast<double>(differ) / n, 2 * p * (1 - p), 0.01);
}

TEST_F(DropoutTest, IdentityAtInferenceAndEdgeProbabilities) {
  std::vector<float> x;
  Var vx = variable(randomTensor(context(), {3, 5}, 3, -1, 1, &x), true);
  Stream stream(context());
  Tape tape(stream);
  EXPECT_EQ(fn::dropout(tape, vx, 0.5f, 1, false), vx);
  {
    NoGrad inference(tape);
    EXPECT_EQ(fn::dropout(tape, vx, 0.5f, 1, true), vx);
  }
  EXPECT_EQ(tape.recordedOps(), 0u);
  Var none = fn::dropout(tape, vx, 0.0f, 1, true);
  Var all = fn::dropout(tape, vx, 1.0f, 1, true);
  stream.submit();
  EXPECT_TRUE(allClose(none->value, x, {0, 0}));
  EXPECT_TRUE(allClose(all->value, std::vector<double>(x.size(), 0.0), {0, 0}));
  EXPECT_THROW(fn::dropout(tape, vx, 1.5f, 1, true), Error);
}

TEST_F(DropoutTest, RunsThroughSmokesvdOp) {
  const Shape shape{2, 3, 5};
  const std::vector<float> x = randomValues(30, 4), g = randomValues(30, 5);
  const OpRun run = runOpCommand("dropout",
                                 {{"x", io::NpyArray::fromFloats(shape, x)}, {"grad_y", io::NpyArray::fromFloats(shape, g)}},
                                 {"y", "grad_x"}, {"p=0.4", "seed=99"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(allClose(run.outputs.at("y").floats, reference(x, 0.4f, 99), shape, {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(run.outputs.at("grad_x").floats, reference(g, 0.4f, 99), shape, {1e-6, 1e-6}));
}

}  // namespace
}  // namespace smokesvd::testing
