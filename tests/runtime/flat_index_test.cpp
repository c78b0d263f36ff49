#include <gtest/gtest.h>

#include <cstring>

#include "runtime/stream.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

class FlatIndexTest : public GpuTest {
 protected:
  // Runs tensor/count_items over n items, flat or with `groups` workgroups; returns the counts and the
  // invocation count the shader saw.
  std::pair<std::vector<uint32_t>, uint32_t> count(uint32_t n, std::optional<std::array<uint32_t, 3>> groups) {
    Tensor counts = Tensor::fromHost(context(), {static_cast<int64_t>(n) + 1}, std::vector<float>(n + 1, 0.0f));
    Stream stream(context());
    const Kernel& kernel = stream.kernel("tensor/count_items", {64, 1, 1});
    struct { uint32_t n; } push{n};
    if (groups)
      stream.dispatch(kernel, {counts}, push, *groups);
    else
      stream.dispatchFlat(kernel, {counts}, push, n);
    stream.submit();
    const std::vector<float> raw = counts.download();
    std::vector<uint32_t> values(raw.size());
    std::memcpy(values.data(), raw.data(), raw.size() * sizeof(float));
    const uint32_t invocations = values.back();
    values.pop_back();
    return {values, invocations};
  }
};

// A flat dispatch of more than 65535 workgroups spans two rows of the grid: every item exactly once.
TEST_F(FlatIndexTest, TwoRowDispatchVisitsEveryItemOnce) {
  const uint32_t n = 64 * 65535 + 100;
  const auto [counts, invocations] = count(n, std::nullopt);
  EXPECT_EQ(invocations, 65535u * 2 * 64);
  uint32_t wrong = 0;
  for (const uint32_t c : counts) wrong += c != 1;
  EXPECT_EQ(wrong, 0u);
}

// One workgroup striding over every item (how deterministic scatters run).
TEST_F(FlatIndexTest, OneWorkgroupStridesOverEveryItemOnce) {
  const auto [counts, invocations] = count(1001, std::array<uint32_t, 3>{1, 1, 1});
  EXPECT_EQ(invocations, 64u);
  for (uint32_t i = 0; i < counts.size(); ++i) ASSERT_EQ(counts[i], 1u) << "item " << i;
}

}  // namespace
}  // namespace smokesvd::testing
