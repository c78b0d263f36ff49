#include <gtest/gtest.h>

#include <cmath>

#include "nets/functional/timestep_embedding.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class TimestepEmbeddingTest : public GpuTest {};

std::vector<double> reference(const std::vector<float>& t, int64_t dim, const ops::TimestepEmbeddingParams& p) {
  const int64_t half = dim / 2;
  std::vector<double> y(t.size() * static_cast<std::size_t>(dim), 0.0);
  for (std::size_t n = 0; n < t.size(); ++n)
    for (int64_t j = 0; j < half; ++j) {
      const double frequency = std::exp(-std::log(static_cast<double>(p.maxPeriod)) * static_cast<double>(j) /
                                        (static_cast<double>(half) - p.frequencyShift));
      const double angle = t[n] * frequency;
      const double first = p.cosineFirst ? std::cos(angle) : std::sin(angle);
      const double second = p.cosineFirst ? std::sin(angle) : std::cos(angle);
      y[n * dim + j] = first;
      y[n * dim + half + j] = second;
    }
  return y;
}

TEST_F(TimestepEmbeddingTest, MatchesReferenceForBothConventions) {
  // Integer timesteps up to 999: float32 angles near 1000 carry ~6e-5 of rounding (worst error seen 3.3e-5).
  const std::vector<float> t{0, 1, 7, 250, 999};
  for (const auto& [dim, params] : {std::pair{int64_t{8}, ops::TimestepEmbeddingParams{}},
                                    std::pair{int64_t{9}, ops::TimestepEmbeddingParams{}},
                                    std::pair{int64_t{33}, ops::TimestepEmbeddingParams{10000.0f, 0.0f, true}},
                                    std::pair{int64_t{6}, ops::TimestepEmbeddingParams{100.0f, 0.0f, false}}}) {
    SCOPED_TRACE(::testing::Message() << "dim " << dim << " shift " << params.frequencyShift << " cos first "
                                      << params.cosineFirst);
    Var vt = variable(Tensor::fromHost(context(), {static_cast<int64_t>(t.size())}, t), true);
    Stream stream(context());
    Tape tape(stream);
    Var y = fn::timestepEmbedding(tape, vt, dim, params);
    stream.submit();
    EXPECT_FALSE(y->requiresGrad);
    EXPECT_EQ(y->value.shape(), (Shape{static_cast<int64_t>(t.size()), dim}));
    EXPECT_TRUE(allClose(y->value, reference(t, dim, params), {1e-4, 0}));
  }
}

TEST_F(TimestepEmbeddingTest, RejectsTooSmallDim) {
  Var t = variable(Tensor::fromHost(context(), {1}, std::vector<float>{3}));
  Stream stream(context());
  Tape tape(stream);
  EXPECT_THROW(fn::timestepEmbedding(tape, t, 2), Error);  // half - shift = 0 (DDPM convention)
  EXPECT_THROW(fn::timestepEmbedding(tape, t, 0), Error);
  EXPECT_NO_THROW(fn::timestepEmbedding(tape, t, 2, {10000.0f, 0.0f, false}));
}

// The runner's timestep embedding on integer timesteps; asking for a gradient is an error.
TEST(TimestepEmbeddingCommand, EmbedsIntegerTimesteps) {
  const io::NpyArray t = io::NpyArray::fromInts({2}, {0, 3});
  const OpRun run = runOpCommand("timestep_embedding", {{"t", t}}, {"y"}, {"dim=4", "shift=0", "cos_first=1"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  // half = 2, f = (1, 1/100): y[n] = [cos(t), cos(t/100), sin(t), sin(t/100)]
  EXPECT_TRUE(allClose(run.outputs.at("y").floats,
                       std::vector<double>{1, 1, 0, 0, std::cos(3.0), std::cos(0.03), std::sin(3.0), std::sin(0.03)},
                       {2, 4}, {1e-6, 0}));
  const OpRun gradient = runOpCommand("timestep_embedding",
                                      {{"t", t}, {"grad_y", io::NpyArray::fromFloats({2, 4}, std::vector<float>(8, 1))}},
                                      {"y"}, {"dim=4"});
  EXPECT_NE(gradient.exitCode, 0);
}

}  // namespace
}  // namespace smokesvd::testing
