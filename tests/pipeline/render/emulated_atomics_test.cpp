// The scattering adjoints (render backward, lift backward) on a context that treats the device as lacking
// float32 atomic add, so their compare-and-swap variants run: the same finite-difference checks as the
// float-atomic variants get in renderer_test.cpp and lift_rotate_test.cpp.
#include <gtest/gtest.h>

#include "runtime/context.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/render/adjoint_checks.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

class EmulatedAtomicsTest : public ::testing::Test {
 protected:
  static Context& emulated() { return sharedContext(ContextOptions{.emulateFloatAtomics = true}); }
  void TearDown() override { expectNoValidationMessages(emulated()); }
};

TEST_F(EmulatedAtomicsTest, ContextReportsNoFloatAtomics) { EXPECT_FALSE(emulated().info().float32AtomicAdd); }

TEST_F(EmulatedAtomicsTest, RenderBackwardMatchesFiniteDifferences) {
  expectRenderBackwardMatchesFiniteDifferences(emulated(), unlitSettings());
  expectRenderBackwardMatchesFiniteDifferences(emulated(), litSettings());
}

TEST_F(EmulatedAtomicsTest, LiftBackwardMatchesFiniteDifferences) {
  expectLiftBackwardMatchesFiniteDifferences(emulated());
}

}  // namespace
}  // namespace smokesvd::testing
