#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "runtime/kernel.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class FiniteCheckTest : public GpuTest {
 protected:
  StreamOptions checked() const { return {.checkFinite = true}; }
};

// The message submit() throws, or "" if it throws nothing.
std::string submitError(Stream& stream) {
  try {
    stream.submit();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

// An op fed a NaN: the first dispatch that writes one is named, with its binding and the element.
TEST_F(FiniteCheckTest, NamesTheShaderBindingAndElementOfAPlantedNan) {
  std::vector<float> values = randomValues(2 * 3 * 5, 1);
  values[17] = std::numeric_limits<float>::quiet_NaN();
  const Tensor x = Tensor::fromHost(context(), {2, 3, 5}, values);
  Tensor y(context(), {2, 3, 5}), z(context(), {2, 3, 5});
  Stream stream(context(), checked());
  ops::fill(stream, z, 1.0f);
  ops::fill(stream, y, 0.0f);  // a NaN written over the very same NaN bits would go unseen
  ops::scale(stream, x, 2.0f, y);
  ops::add(stream, y, z, z);
  const std::string error = submitError(stream);
  EXPECT_NE(error.find("NaN written by dispatch 3, shader 'tensor/axpby', binding 2 'Output'"), std::string::npos)
      << error;
  EXPECT_NE(error.find("element 17 of 30, index [1, 0, 2] of [2, 3, 5]"), std::string::npos) << error;
}

TEST_F(FiniteCheckTest, TellsInfinitiesFromNan) {
  const Tensor x = Tensor::fromHost(context(), {7}, std::vector<float>{0, 1, 2, 3e38f, -3e38f, 5, 6});
  Tensor y(context(), {7});
  Stream stream(context(), checked());
  ops::fill(stream, y, 0.0f);
  ops::scale(stream, x, 10.0f, y);  // 3e39 overflows to +Inf, -3e39 to -Inf
  const std::string error = submitError(stream);
  EXPECT_NE(error.find("+Inf written by dispatch 2"), std::string::npos) << error;
  EXPECT_NE(error.find("element 3 of 7"), std::string::npos) << error;
}

// A recording submitted again is checked again: its report slots are reset by the recording itself.
TEST_F(FiniteCheckTest, ChecksEveryRunOfAResubmittedRecording) {
  std::vector<float> values = randomValues(1000, 2);
  const Tensor x = Tensor::fromHost(context(), {10, 100}, values);
  Tensor y(context(), {10, 100});
  Stream stream(context(), checked());
  ops::scale(stream, x, 3.0f, y);
  EXPECT_EQ(submitError(stream), "");
  values[999] = -std::numeric_limits<float>::infinity();
  x.upload(values);
  EXPECT_NE(submitError(stream).find("-Inf written by dispatch 1, shader 'tensor/axpby'"), std::string::npos);
  values[999] = 0.0f;
  x.upload(values);
  EXPECT_EQ(submitError(stream), "");
}

// Elements a dispatch does not write are not its doing, whatever they hold: a fill of the first half of
// a NaN-poisoned buffer passes, a fill of it with NaN does not.
TEST_F(FiniteCheckTest, JudgesADispatchOnlyByWhatItWrote) {
  const Tensor y = poisonedTensor(context(), {8});
  struct {
    uint32_t n;
    float value;
  } half{4, 1.0f}, nan{4, std::numeric_limits<float>::quiet_NaN()};
  Stream stream(context(), checked());
  const Kernel& fill = stream.kernel("tensor/fill");
  stream.dispatchFlat(fill, {y}, half, 1);
  EXPECT_EQ(submitError(stream), "");
  stream.reset();
  stream.dispatchFlat(fill, {y}, half, 1);
  stream.dispatchFlat(fill, {y}, nan, 1);
  EXPECT_NE(submitError(stream).find("NaN written by dispatch 2, shader 'tensor/fill', binding 0 'Output', at element 0 "
                                     "of 8;"),
            std::string::npos);
}

// With the check on, a clean run computes exactly what it computes without.
TEST_F(FiniteCheckTest, ACleanRunGivesIdenticalResults) {
  const Tensor a = randomTensor(context(), {3, 37}, 4), b = randomTensor(context(), {3, 37}, 5);
  auto run = [&](StreamOptions options) {
    Tensor sum(context(), {3, 37}), product(context(), {3, 37}), out(context(), {3, 37});
    Stream stream(context(), options);
    ops::add(stream, a, b, sum);
    ops::mul(stream, sum, a, product);
    ops::axpby(stream, 0.5f, product, -2.0f, b, out);
    stream.submit();
    stream.submit();
    return out.download();
  };
  const std::vector<float> plain = run({}), checkedRun = run(checked());
  ASSERT_EQ(plain.size(), checkedRun.size());
  for (std::size_t i = 0; i < plain.size(); ++i)
    EXPECT_EQ(std::bit_cast<uint32_t>(plain[i]), std::bit_cast<uint32_t>(checkedRun[i])) << i;
}

// What the check scans comes from the reflected bindings: integer blocks and blocks named *NonFinite
// are left alone, float bits in `uint` blocks (compare-and-swap atomics) are scanned.
TEST_F(FiniteCheckTest, ScansOnlyFloatBuffersMeantToBeFinite) {
  EXPECT_FALSE(context().kernel({"physics/advect_window", {64, 1, 1}, {}}).bindings()[1].finiteFloats);
  const std::vector<BindingInfo>& prepare = context().kernel({"physics/advect_mc_prepare", {8, 8, 1}, {}}).bindings();
  EXPECT_TRUE(prepare[3].finiteFloats);
  EXPECT_FALSE(prepare[5].finiteFloats);  // BoundsNonFinite: an empty range is (+inf, -inf)
  EXPECT_TRUE(context().kernel({"render/march_adjoint_cas", {64, 1, 1}, {}}).bindings().back().finiteFloats);
}

}  // namespace
}  // namespace smokesvd::testing
