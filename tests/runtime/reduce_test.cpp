#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "nets/ops/reduce.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class ReduceTest : public GpuTest, public ::testing::WithParamInterface<int64_t> {};

TEST_P(ReduceTest, SumMaxMeanMatchDoubleReference) {
  const int64_t n = GetParam();
  std::vector<float> x;
  Tensor tx = randomTensor(context(), {n}, static_cast<uint64_t>(n), -1, 1, &x);
  double sum = 0, absSum = 0;
  for (float v : x) {
    sum += v;
    absSum += std::abs(v);
  }
  const double max = *std::max_element(x.begin(), x.end());
  Tensor outSum = poisonedTensor(context(), {1});
  Tensor outMax = poisonedTensor(context(), {1});
  Tensor outMean = poisonedTensor(context(), {1});
  Stream stream(context());
  ops::reduceAll(stream, ops::Reduction::Sum, tx, outSum);
  ops::reduceAll(stream, ops::Reduction::Max, tx, outMax);
  ops::reduceAll(stream, ops::Reduction::Mean, tx, outMean);
  stream.submit();
  // Float accumulation error grows with the magnitude of what is added: bound it by eps * sum |x|.
  const double sumTolerance = 1e-6 * absSum + 1e-6;
  EXPECT_TRUE(allClose(outSum, std::vector<double>{sum}, {sumTolerance, 0}));
  EXPECT_TRUE(allClose(outMax, std::vector<double>{max}, {0, 0}));
  EXPECT_TRUE(allClose(outMean, std::vector<double>{sum / static_cast<double>(n)},
                       {sumTolerance / static_cast<double>(n), 1e-6}));
}

INSTANTIATE_TEST_SUITE_P(SizesUpTo1e7, ReduceTest,
                         ::testing::Values(1, 2, 3, 7, 255, 1023, 4097, 65535, 1000001, 9999991));

}  // namespace
}  // namespace smokesvd::testing
