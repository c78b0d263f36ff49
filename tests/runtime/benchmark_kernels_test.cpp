// The kernels only `smokesvd bench` dispatches, checked by value: the storage-read copy, the loop-FMA peak
// probe (against its recurrence on the CPU) and the empty kernel of the dispatch-cost figure.
#include <gtest/gtest.h>

#include <cmath>

#include "nets/ops/elementwise.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class BenchmarkKernelsTest : public GpuTest {};

TEST_F(BenchmarkKernelsTest, StorageCopyCopiesEveryElement) {
  for (const int64_t n : {1, 7, 1001, 4099}) {
    std::vector<float> x;
    Tensor tx = randomTensor(context(), {n}, 11, -3, 3, &x);
    Tensor ty = poisonedTensor(context(), {n});
    Stream stream(context());
    struct { uint32_t n; } push{static_cast<uint32_t>(n)};
    stream.dispatchFlat(stream.kernel("tensor/copy_storage", {64, 1, 1}), {tx, ty}, push, static_cast<uint64_t>((n + 3) / 4));
    stream.submit();
    EXPECT_TRUE(allClose(ty, x, {0, 0})) << "n = " << n;
  }
}

// result[id] = sum over 8 chains of the 4 equal lanes of a_j, a_j <- a_j * m + d from a_j = id * 1e-6 + j.
TEST_F(BenchmarkKernelsTest, FmaPeakComputesItsChains) {
  constexpr int64_t kInvocations = 64 * 37;  // whole workgroups: the probe has no bounds check
  struct {
    int32_t iterations;
    float seed;
  } push{53, 3.0f};
  Tensor out = poisonedTensor(context(), {kInvocations});
  Stream stream(context());
  stream.dispatchFlat(stream.kernel("bench/fma_peak", {64, 1, 1}), {out}, push, kInvocations);
  stream.submit();
  const double m = static_cast<double>(0.999999f), d = static_cast<double>(push.seed * 1e-7f);
  std::vector<double> expected(kInvocations);
  for (int64_t id = 0; id < kInvocations; ++id) {
    double sum = 0;
    for (int j = 0; j < 8; ++j) {
      double a = static_cast<double>(static_cast<float>(id) * 1e-6f + static_cast<float>(j));
      for (int i = 0; i < push.iterations; ++i) a = a * m + d;
      sum += 4 * a;
    }
    expected[static_cast<std::size_t>(id)] = sum;
  }
  EXPECT_TRUE(allClose(out, expected, {1e-5, 1e-5}));
}

// The empty kernel binds nothing and writes nothing: dispatched between a fill and a copy of one batch, it
// leaves the copy exact (and raises no validation message, checked by the fixture).
TEST_F(BenchmarkKernelsTest, EmptyDispatchesLeaveABatchIntact) {
  constexpr int64_t n = 333;
  Tensor x = poisonedTensor(context(), {n});
  Tensor y = poisonedTensor(context(), {n});
  Stream stream(context());
  ops::fill(stream, x, 1.25f);
  const Kernel& empty = stream.kernel("tensor/empty", {64, 1, 1});
  for (int i = 0; i < 3; ++i) stream.dispatch(empty, std::span<const Arg>{}, nullptr, 0, {5, 1, 1});
  ops::copy(stream, x, y);
  stream.submit();
  EXPECT_TRUE(allClose(y, std::vector<double>(n, 1.25), {0, 0}));
}

}  // namespace
}  // namespace smokesvd::testing
