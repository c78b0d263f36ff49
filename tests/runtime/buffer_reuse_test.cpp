#include <gtest/gtest.h>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

// Unguarded: a guarded tensor's memory is written by the host, so recordings never reuse it.
class BufferReuseTest : public GpuTest {
 protected:
  Context& context() { return unguardedTestContext(); }
  static constexpr int64_t kN = 1000;
  std::vector<double> times(const std::vector<float>& values, double factor) {
    std::vector<double> scaled(values.begin(), values.end());
    for (double& v : scaled) v = static_cast<double>(static_cast<float>(v * factor));
    return scaled;
  }
};

// a = 2x; b = 3a; a dies; c = 5x gets a's memory. c's write must wait for b's read of a: the
// write-after-read barrier on the reused memory is the one barrier more than without reuse.
TEST_F(BufferReuseTest, ADeadTensorBacksALaterOneBehindABarrier) {
  std::vector<float> values;
  const Tensor x = randomTensor(context(), {kN}, 1, -1, 1, &values);
  for (const bool reuse : {false, true}) {
    Stream stream(context(), {.reuseBuffers = reuse});
    Tensor a(context(), {kN});
    ops::scale(stream, x, 2.0f, a);
    Tensor b(context(), {kN});
    ops::scale(stream, a, 3.0f, b);
    const VkBuffer aMemory = a.buffer().handle();
    a = Tensor{};
    Tensor c(context(), {kN});
    ops::scale(stream, x, 5.0f, c);
    EXPECT_EQ(c.buffer().handle() == aMemory, reuse);
    EXPECT_EQ(stream.memory().reusedBuffers, reuse ? 1u : 0u);
    EXPECT_EQ(stream.memory().heldBuffers, reuse ? 3u : 4u);
    if (!stream.checksFinite()) {
      EXPECT_EQ(stream.barrierCount(), reuse ? 2u : 1u);
    }
    for (int run = 0; run < 3; ++run) {
      stream.submit();
      EXPECT_TRUE(allClose(b, times(values, 6.0), {0, 0}));
      EXPECT_TRUE(allClose(c, times(values, 5.0), {0, 0}));
    }
  }
}

// Of the dead memories, one that no command since the last barrier touched is taken first: reusing it
// costs no barrier.
TEST_F(BufferReuseTest, PrefersMemoryThatNeedsNoBarrier) {
  const Tensor x = randomTensor(context(), {kN}, 5);
  Stream stream(context());
  Tensor p(context(), {kN}), q(context(), {kN}), r(context(), {kN}), s(context(), {kN}), t(context(), {kN});
  ops::scale(stream, x, 2.0f, p);
  ops::scale(stream, x, 3.0f, q);
  ops::scale(stream, q, 5.0f, r);  // barrier 1
  ops::add(stream, r, p, t);       // barrier 2
  Tensor u(context(), {kN});
  ops::scale(stream, p, 7.0f, u);  // p is read after barrier 2, q is not
  const VkBuffer qMemory = q.buffer().handle();
  p = Tensor{};
  q = Tensor{};
  Tensor v(context(), {kN});
  ops::scale(stream, x, 11.0f, v);
  EXPECT_EQ(v.buffer().handle(), qMemory);
  if (!stream.checksFinite()) {
    EXPECT_EQ(stream.barrierCount(), 2u);
  }
  stream.submit();
}

// Tensors whose contents come from the host, and tensors made before the recording began, keep memory of
// their own: the recording does not decide what they hold.
TEST_F(BufferReuseTest, HostDataAndTensorsFromBeforeKeepTheirMemory) {
  std::vector<float> values;
  const Tensor x = randomTensor(context(), {kN}, 2, -1, 1, &values);
  Tensor before(context(), {kN});
  Stream stream(context());
  Tensor a(context(), {kN});
  ops::scale(stream, x, 2.0f, a);
  Tensor b(context(), {kN});
  ops::scale(stream, a, 1.0f, b);
  a = Tensor{};
  const Tensor uploaded = Tensor::fromHost(context(), {kN}, std::vector<float>(kN, 7.0f));
  ops::add(stream, uploaded, b, before);
  EXPECT_EQ(stream.memory().reusedBuffers, 0u);
  stream.submit();
  stream.submit();
  std::vector<double> expected = times(values, 2.0);
  for (double& v : expected) v = static_cast<double>(static_cast<float>(v) + 7.0f);
  EXPECT_TRUE(allClose(before, expected, {0, 0}));
}

// A reused memory may be read from anywhere, but written only by its recording until reset().
TEST_F(BufferReuseTest, AReusedBufferIsWrittenOnlyByItsRecording) {
  const Tensor x = randomTensor(context(), {kN}, 3);
  Stream stream(context());
  Tensor a(context(), {kN});
  ops::scale(stream, x, 2.0f, a);
  Tensor b(context(), {kN});
  ops::scale(stream, a, 3.0f, b);
  a = Tensor{};
  Tensor c(context(), {kN});
  ops::scale(stream, x, 5.0f, c);
  ASSERT_EQ(stream.memory().reusedBuffers, 1u);
  stream.submit();

  try {
    c.upload(std::vector<float>(kN, 1.0f));
    ADD_FAILURE() << "an upload into reused memory went through";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("upload to tensor [1000]: writing 4000 bytes from the host into a "
                                             "buffer that a recorded stream also uses for earlier tensors"),
              std::string::npos)
        << error.what();
  }
  Stream other(context());
  Tensor d(context(), {kN});
  ops::scale(other, c, 1.0f, d);  // reading is fine
  EXPECT_THROW(ops::fill(other, c, 0.0f), Error);
  other.submit();
  EXPECT_TRUE(allClose(d, c.download(), {0, 0}));

  stream.reset();
  c.upload(std::vector<float>(kN, 1.0f));
  EXPECT_TRUE(allClose(c, std::vector<double>(kN, 1.0), {0, 0}));
}

// The stream's figures: what the recording holds, and what the pool hands out and peaks at.
TEST_F(BufferReuseTest, TheRecordingAndThePoolReportTheirMemory) {
  BufferPool& pool = context().buffers();
  const Tensor x = randomTensor(context(), {kN}, 4);
  const VkDeviceSize bytes = BufferPool::sizeClass(kN * sizeof(float));
  pool.resetPeaks();
  const BufferPool::Stats start = pool.stats();
  {
    Stream stream(context());
    std::vector<Tensor> chain{x};
    for (int k = 0; k < 6; ++k) {
      Tensor next(context(), {kN});
      ops::scale(stream, chain.back(), 0.5f, next);
      if (chain.size() > 1) chain.erase(chain.begin());  // only the latest two stay alive
      chain.push_back(next);
    }
    const StreamMemory memory = stream.memory();
    EXPECT_EQ(memory.heldBytes, memory.heldBuffers * bytes);
    EXPECT_EQ(memory.reusedBuffers, 3u);  // the 4th to 6th tensor reuse the memory of the 1st to 3rd
    EXPECT_EQ(memory.heldBytes, 4 * bytes);  // x and three
    EXPECT_EQ(memory.bytesWithoutReuse(), 7 * bytes);
    stream.submit();
    EXPECT_LE(pool.stats().peakLiveBytes, start.liveBytes + 4 * bytes);
  }
  EXPECT_EQ(pool.stats().liveBytes, start.liveBytes);
  EXPECT_EQ(pool.stats().allocatedBytes, pool.stats().liveBytes + pool.stats().idleBytes);
}

}  // namespace
}  // namespace smokesvd::testing
