#include <gtest/gtest.h>

#include <cmath>

#include "runtime/context.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"
#include "runtime/tensor_guards.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

class TensorGuardsTest : public ::testing::Test {
 protected:
  static Context& guarded() { return sharedContext(ContextOptions{.guardTensors = true}); }
  void TearDown() override { expectNoValidationMessages(guarded()); }
  // y[i] = value for i < n (whole vec4s), n may exceed the tensor.
  static void fill(const Tensor& y, uint32_t n, float value) {
    Stream stream(guarded());
    struct {
      uint32_t n;
      float value;
    } push{n, value};
    stream.dispatchFlat(stream.kernel("tensor/fill"), {y}, push, (n + 3) / 4);
    stream.submit();
  }
};

TEST_F(TensorGuardsTest, NewTensorsReadNaN) {
  const Tensor tensor(guarded(), {3, 5});
  for (float value : tensor.download()) EXPECT_TRUE(std::isnan(value));
  EXPECT_EQ(tensor.boundBytes(), 64u + TensorGuards::kGuardBytes);
}

TEST_F(TensorGuardsTest, WritesIntoTheVec4PaddingAreAllowed) {
  guarded().tensorGuards()->clear();
  const Tensor tensor(guarded(), {7});
  fill(tensor, 7, 2.0f);  // the second vec4 covers element 7, in the padding
  EXPECT_EQ(tensor.download(), std::vector<float>(7, 2.0f));
  EXPECT_TRUE(guarded().tensorGuards()->violations().empty());
}

TEST_F(TensorGuardsTest, AWritePastTheEndIsReported) {
  guarded().tensorGuards()->clear();
  const Tensor tensor(guarded(), {7});
  fill(tensor, 7 + 1 + 8, 2.0f);  // two vec4s past the padding
  const std::vector<std::string> violations = guarded().tensorGuards()->violations();
  ASSERT_EQ(violations.size(), 1u);
  EXPECT_NE(violations[0].find("tensor [7]: 8 guard words written past its end, the first 0 floats after"),
            std::string::npos)
      << violations[0];
  guarded().tensorGuards()->clear();
  EXPECT_TRUE(guarded().tensorGuards()->violations().empty());
}

TEST_F(TensorGuardsTest, OnlyGuardedContextsHaveGuards) {
  Context plain;
  EXPECT_EQ(plain.tensorGuards(), nullptr);
  EXPECT_EQ(Tensor(plain, {3}).boundBytes(), 12u);
}

}  // namespace
}  // namespace smokesvd::testing
