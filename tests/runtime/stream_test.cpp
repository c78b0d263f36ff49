#include <gtest/gtest.h>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "runtime/kernel.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class StreamTest : public GpuTest {};

// x_{k+1} = x_k + c for 100 steps, ping-ponging between two buffers: each dispatch reads what the one
// before it wrote and overwrites what the one before that read, so every barrier must be there.
TEST_F(StreamTest, HundredDependentDispatchesNeedEveryBarrier) {
  const int64_t n = 100003;
  std::vector<float> start;
  Tensor ping = randomTensor(context(), {n}, 9, -1, 1, &start);
  Tensor pong = poisonedTensor(context(), {n});
  Tensor step = Tensor::fromHost(context(), {n}, std::vector<float>(n, 0.5f));
  Stream stream(context());
  for (int k = 0; k < 100; ++k) {
    const Tensor& from = k % 2 == 0 ? ping : pong;
    const Tensor& to = k % 2 == 0 ? pong : ping;
    ops::axpby(stream, 1.0f, from, 1.0f, step, to);
  }
  EXPECT_EQ(stream.dispatchCount(), 100u);
  if (!stream.checksFinite()) {  // the finite check adds barriers of its own
    EXPECT_EQ(stream.barrierCount(), 99u);
  }
  stream.submit();
  std::vector<double> expected(start.begin(), start.end());
  for (double& value : expected) value += 50.0;
  EXPECT_TRUE(allClose(ping, expected, {1e-4, 1e-6}));
}

TEST_F(StreamTest, IndependentDispatchesGetNoBarrier) {
  Tensor x = randomTensor(context(), {1000}, 1);
  std::vector<Tensor> outputs;
  Stream stream(context());
  for (int k = 0; k < 10; ++k) {
    outputs.emplace_back(context(), Shape{1000});
    ops::scale(stream, x, static_cast<float>(k), outputs.back());
  }
  if (!stream.checksFinite()) {
    EXPECT_EQ(stream.barrierCount(), 0u);
  }
  stream.submit();
}

TEST_F(StreamTest, ResubmitRunsTheSameRecordingAgain) {
  Tensor x = Tensor::fromHost(context(), {5}, std::vector<float>(5, 1.0f));
  Stream stream(context());
  ops::scale(stream, x, 2.0f, x);
  stream.submit();
  stream.submit();
  stream.submit();
  EXPECT_TRUE(allClose(x, std::vector<double>(5, 8.0), {0, 0}));
  EXPECT_THROW(ops::fill(stream, x, 0.0f), Error);  // recording is closed until reset()
  stream.reset();
  ops::fill(stream, x, 0.0f);
  stream.submit();
  EXPECT_TRUE(allClose(x, std::vector<double>(5, 0.0), {0, 0}));
}

TEST_F(StreamTest, CopyAndFillZeroAreOrdered) {
  std::vector<float> values;
  Tensor a = randomTensor(context(), {333}, 5, -1, 1, &values);
  Tensor b = poisonedTensor(context(), {333});
  Tensor c = poisonedTensor(context(), {333});
  Stream stream(context());
  stream.copy(a, b);
  ops::scale(stream, b, 2.0f, c);  // reads b after the transfer wrote it
  stream.fillZero(b);              // overwrites b after the dispatch read it
  stream.submit();
  std::vector<double> doubled(values.begin(), values.end());
  for (double& v : doubled) v *= 2;
  EXPECT_TRUE(allClose(c, doubled));
  EXPECT_TRUE(allClose(b, std::vector<double>(333, 0.0), {0, 0}));
}

// Parts of odd sizes gathered into a whole at offsets with gaps, doubled there by a dispatch that reads the
// gather's writes, and scattered back into poisoned parts: every element of each part comes back doubled,
// the gaps of the whole keep what they held, and the transfers need no barrier between them.
TEST_F(StreamTest, GatherAndScatterMoveEachPartToItsOffsetAndBack) {
  const std::vector<int64_t> sizes{5, 1, 333, 8};
  const std::vector<int64_t> offsets{0, 7, 9, 400};
  std::vector<Tensor> parts, back;
  std::vector<std::vector<float>> values;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    values.emplace_back();
    parts.push_back(randomTensor(context(), {sizes[i]}, 30 + i, -1, 1, &values.back()));
    back.push_back(poisonedTensor(context(), {sizes[i]}));
  }
  Tensor whole = Tensor::fromHost(context(), {413}, std::vector<float>(413, -7.0f));
  Tensor doubled = poisonedTensor(context(), {413});
  Stream stream(context());
  stream.gather(parts, offsets, whole);
  ops::scale(stream, whole, 2.0f, doubled);
  stream.scatter(doubled, offsets, back);
  if (!stream.checksFinite()) {
    EXPECT_EQ(stream.barrierCount(), 2u);  // gather -> scale -> scatter
  }
  stream.submit();
  const std::vector<float> wholeValues = whole.download();
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    SCOPED_TRACE("part " + std::to_string(i));
    std::vector<double> expected(values[i].begin(), values[i].end());
    EXPECT_TRUE(allClose(std::vector<float>(wholeValues.begin() + offsets[i], wholeValues.begin() + offsets[i] + sizes[i]),
                         expected, {0, 0}));
    for (double& v : expected) v *= 2;
    EXPECT_TRUE(allClose(back[i], expected, {0, 0}));
  }
  for (const int64_t gap : {5, 6, 8, 342, 399, 408, 412}) EXPECT_EQ(wholeValues[gap], -7.0f) << gap;
}

TEST_F(StreamTest, GatherAndScatterRefuseOverlappingOrSharedParts) {
  Tensor a = randomTensor(context(), {6}, 1);
  Tensor b = randomTensor(context(), {6}, 2);
  Tensor whole(context(), {12});
  Stream stream(context());
  const std::vector<Tensor> two{a, b};
  EXPECT_THROW(stream.gather(two, std::vector<int64_t>{0, 5}, whole), Error);   // a ends at 6
  EXPECT_THROW(stream.gather(two, std::vector<int64_t>{6, 0}, whole), Error);   // not ascending
  EXPECT_THROW(stream.gather(two, std::vector<int64_t>{0, 7}, whole), Error);   // b ends past 12
  EXPECT_THROW(stream.gather(two, std::vector<int64_t>{0}, whole), Error);      // one offset for two parts
  EXPECT_THROW(stream.gather(std::vector<Tensor>{a, whole}, std::vector<int64_t>{0, 6}, whole), Error);
  EXPECT_THROW(stream.scatter(whole, std::vector<int64_t>{0, 6}, std::vector<Tensor>{a, a}), Error);
}

TEST_F(StreamTest, DerivedTensorsAreKeptUntilTheirSourceIsWritten) {
  Tensor source = randomTensor(context(), {8}, 1);
  Tensor other = randomTensor(context(), {8}, 2);
  Tensor kept(context(), {8});
  Stream stream(context());
  ops::scale(stream, source, 2.0f, kept);
  stream.keepDerived(source, "doubled", kept);
  EXPECT_EQ(&stream.derived(source, "doubled").buffer(), &kept.buffer());
  EXPECT_FALSE(stream.derived(source, "tripled").defined());
  EXPECT_FALSE(stream.derived(other, "doubled").defined());
  ops::scale(stream, source, 2.0f, other);  // reads the source: still kept
  EXPECT_TRUE(stream.derived(source, "doubled").defined());
  stream.copy(other, source);               // writes it: gone
  EXPECT_FALSE(stream.derived(source, "doubled").defined());
  stream.keepDerived(source, "doubled", kept);
  stream.submit();
  stream.reset();
  EXPECT_FALSE(stream.derived(source, "doubled").defined());
}

TEST_F(StreamTest, TimesRegionsOnTheGpu) {
  if (!context().info().timestamps) GTEST_SKIP() << "device has no timestamps";
  Tensor x = randomTensor(context(), {1 << 20}, 1);
  Tensor y(context(), {1 << 20});
  Stream stream(context(), {.profileDispatches = true});
  stream.beginRegion("both");
  ops::scale(stream, x, 2.0f, y);
  ops::scale(stream, y, 2.0f, x);
  stream.endRegion();
  stream.submit();
  const std::vector<RegionTime> times = stream.regionTimes();
  ASSERT_EQ(times.size(), 3u);
  EXPECT_EQ(times[0].name, "both");
  EXPECT_EQ(times[1].name, "tensor/axpby");
  EXPECT_GT(times[1].nanoseconds, 0);
  EXPECT_GE(times[0].nanoseconds, times[1].nanoseconds);
  EXPECT_TRUE(times[0].detail.empty());
}

// A profiled dispatch carries its grid, the kernel's specialisation constants and its push constants, which
// tell the reader of a profile the shape of each slow dispatch (smokesvd bench --profile-dispatches).
TEST_F(StreamTest, ProfiledDispatchesCarryTheirGridConstantsAndPushConstants) {
  if (!context().info().timestamps) GTEST_SKIP() << "device has no timestamps";
  const Tensor a = randomTensor(context(), {512}, 1), b = randomTensor(context(), {512}, 2);
  Tensor y(context(), {512});
  Stream stream(context(), {.profileDispatches = true});
  struct { uint32_t n; } push{512};
  stream.dispatch(stream.kernel("tensor/binary", {64, 1, 1}, {2}), {asVec4(a), asVec4(b), Arg(y)}, push, {2, 1, 1});
  stream.submit();
  const std::vector<RegionTime> times = stream.regionTimes();
  ASSERT_EQ(times.size(), 1u);
  EXPECT_EQ(times[0].name, "tensor/binary");
  EXPECT_EQ(times[0].detail, "groups 2x1x1; constants 2; push 512");
  const std::vector<float> av = a.download(), bv = b.download(), yv = y.download();
  for (std::size_t i = 0; i < yv.size(); ++i) ASSERT_EQ(yv[i], av[i] * bv[i]) << i;  // OP 2: the product
}

TEST_F(StreamTest, WrongArgumentCountIsAnError) {
  Tensor x(context(), {4});
  Stream stream(context());
  struct { uint32_t n; } push{4};
  EXPECT_THROW(stream.dispatchFlat(stream.kernel("tensor/copy", {64, 1, 1}), {x}, push, 1), Error);
}

TEST_F(StreamTest, KernelBindingsAreReflectedFromSpirv) {
  const Kernel& kernel = context().kernel({"tensor/axpby", {64, 1, 1}, {}});
  ASSERT_EQ(kernel.bindings().size(), 3u);
  EXPECT_EQ(kernel.bindings()[0].kind, BindingKind::UniformTexelBuffer);
  EXPECT_EQ(kernel.bindings()[1].kind, BindingKind::UniformTexelBuffer);
  EXPECT_EQ(kernel.bindings()[2].kind, BindingKind::StorageBuffer);
  EXPECT_FALSE(kernel.bindings()[2].reads);
  EXPECT_TRUE(kernel.bindings()[2].writes);
  const Kernel& storageCopy = context().kernel({"tensor/copy_storage", {64, 1, 1}, {}});
  EXPECT_TRUE(storageCopy.bindings()[0].reads);
  EXPECT_FALSE(storageCopy.bindings()[0].writes);
  EXPECT_TRUE(kernel.hasPushConstants());
}

TEST_F(StreamTest, UnknownShaderIsAnError) {
  EXPECT_THROW(context().kernel({"tensor/no_such_shader", {64, 1, 1}, {}}), Error);
}

}  // namespace
}  // namespace smokesvd::testing

namespace smokesvd::testing {
namespace {

// Guards the guard: misuse reported by the validation layer reaches the test fixture.
TEST_F(StreamTest, ValidationLayerMessagesAreCaught) {
  ASSERT_TRUE(context().validationEnabled());
  Buffer buffer(context(), 1024);
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.handle();
  info.format = VK_FORMAT_R32_SFLOAT;
  info.offset = 4;  // below minTexelBufferOffsetAlignment (16 on lavapipe): invalid usage
  info.range = 64;
  VkBufferView view = VK_NULL_HANDLE;
  vkCreateBufferView(context().device(), &info, nullptr, &view);
  if (view) vkDestroyBufferView(context().device(), view, nullptr);
  EXPECT_FALSE(context().takeValidationMessages().empty());
}

// Messages nobody took from a context before it was destroyed -- among them those raised by its
// destruction -- are kept for the process (the command line and the test harness check them last).
TEST(ValidationMessagesTest, ThoseOfADestroyedContextAreKeptForTheProcess) {
  ASSERT_TRUE(Context::takeUnreadValidationMessages().empty());
  {
    Context own(ContextOptions{.validation = true});
    Buffer buffer(own, 1024);
    VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
    info.buffer = buffer.handle();
    info.format = VK_FORMAT_R32_SFLOAT;
    info.offset = 4;  // invalid usage, as above
    info.range = 64;
    VkBufferView view = VK_NULL_HANDLE;
    vkCreateBufferView(own.device(), &info, nullptr, &view);
    if (view) vkDestroyBufferView(own.device(), view, nullptr);
  }
  const std::vector<std::string> unread = Context::takeUnreadValidationMessages();
  ASSERT_FALSE(unread.empty());
  EXPECT_NE(unread.front().find("offset"), std::string::npos) << unread.front();
}

}  // namespace
}  // namespace smokesvd::testing
