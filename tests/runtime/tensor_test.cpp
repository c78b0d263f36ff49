#include <gtest/gtest.h>

#include "runtime/buffer.h"
#include "runtime/error.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

class TensorTest : public GpuTest {};

TEST_F(TensorTest, RoundTripsOddSizes) {
  for (int64_t n : {1, 3, 7, 17, 255, 257, 1000, 65537, 1000003}) {
    std::vector<float> values;
    Tensor tensor = randomTensor(context(), {n}, static_cast<uint64_t>(n), -5, 5, &values);
    EXPECT_EQ(tensor.download(), values) << "size " << n;
  }
}

TEST_F(TensorTest, ReportsShapeAndStrides) {
  Tensor tensor(context(), {2, 3, 5, 7});
  EXPECT_EQ(tensor.numel(), 210);
  EXPECT_EQ(tensor.strides(), (Shape{105, 35, 7, 1}));
  EXPECT_EQ(tensor.size(-1), 7);
  EXPECT_THROW(tensor.size(4), Error);
  EXPECT_THROW(tensor.reshaped({3, 3}), Error);
  EXPECT_EQ(tensor.reshaped({210}).numel(), 210);
}

TEST_F(TensorTest, UploadOfWrongSizeIsAnError) {
  Tensor tensor(context(), {4});
  std::vector<float> three(3);
  EXPECT_THROW(tensor.upload(three), Error);
}

TEST_F(TensorTest, OversizedTensorIsAClearError) {
  const uint64_t limit = context().info().maxTensorBytes();
  const int64_t elements = static_cast<int64_t>(limit / sizeof(float)) + 1;
  try {
    Tensor tensor(context(), {elements});
    FAIL() << "expected an Error for a tensor of " << elements << " floats";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("tensor [" + std::to_string(elements) + "]"), std::string::npos) << message;
    EXPECT_NE(message.find("storage-buffer range and texel-buffer size"), std::string::npos) << message;
  }
}

TEST_F(TensorTest, PoolReusesBuffersInSteadyState) {
  BufferPool& pool = context().buffers();
  for (int warmup = 0; warmup < 2; ++warmup) Tensor tensor(context(), {3, 33, 17});
  const std::size_t created = pool.stats().created;
  for (int step = 0; step < 10; ++step) {
    Tensor a(context(), {3, 33, 17});
    Tensor b(context(), {3, 33, 17});
  }
  EXPECT_LE(pool.stats().created, created + 1);  // at most one more for the second live tensor
  const std::size_t afterSteps = pool.stats().created;
  for (int step = 0; step < 10; ++step) {
    Tensor a(context(), {3, 33, 17});
    Tensor b(context(), {3, 33, 17});
  }
  EXPECT_EQ(pool.stats().created, afterSteps);
}

TEST(SizeClass, RoundsUpToPowersOfTwoAndThreeHalves) {
  EXPECT_EQ(BufferPool::sizeClass(1), 256u);
  EXPECT_EQ(BufferPool::sizeClass(256), 256u);
  EXPECT_EQ(BufferPool::sizeClass(257), 384u);
  EXPECT_EQ(BufferPool::sizeClass(384), 384u);
  EXPECT_EQ(BufferPool::sizeClass(385), 512u);
  EXPECT_EQ(BufferPool::sizeClass(1000), 1024u);
}

}  // namespace
}  // namespace smokesvd::testing

namespace smokesvd::testing {
namespace {

// The discrete-GPU path (device-local buffers, staging copies), exercised on whatever device is here.
TEST(StagingTest, RoundTripsAndRunsKernelsThroughStagingBuffers) {
  ContextOptions options;
  options.validation = true;
  options.forceStaging = true;
  Context staged(options);
  ASSERT_FALSE(staged.mappedBuffers());
  {
    std::vector<float> values;
    Tensor x = randomTensor(staged, {1001}, 7, -1, 1, &values);
    EXPECT_EQ(x.buffer().mapped(), nullptr);
    EXPECT_EQ(x.download(), values);
    Tensor y = poisonedTensor(staged, {1001});
    Stream stream(staged);
    stream.copy(x, y);
    stream.submit();
    EXPECT_EQ(y.download(), values);
  }
  const std::vector<std::string> messages = staged.takeValidationMessages();
  EXPECT_TRUE(messages.empty()) << messages.front();
}

}  // namespace
}  // namespace smokesvd::testing
