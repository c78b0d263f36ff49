// Base fixture for every test that touches the GPU: contexts shared by the whole test process, created
// with the Khronos validation layer and its synchronization validation on; a test fails if the layer
// reported anything while it ran, and the process fails if the layer reports anything after the last
// test, while the contexts are destroyed (objects left alive, ...), or from a context a test made itself.
#pragma once

#include <gtest/gtest.h>

#include "runtime/context.h"

namespace smokesvd::testing {

// The process-wide validated context (created on first use). Its tensors are guarded
// (ContextOptions::guardTensors): every tensor, on fresh memory or on a buffer the pool hands out again,
// starts NaN-filled, tape gradients and the outputs kernels write included, so an element no kernel wrote
// never passes a comparison; a guard after each tensor sees writes past its end.
Context& testContext();
// The same without guards, for the tests of what guards change: a guarded tensor's memory is written by
// the host when it is made, so a recording never reuses it (runtime/recording_memory.h), and it is larger.
Context& unguardedTestContext();
// A process-wide context with these options (device, forceStaging, emulateFloatAtomics, guardTensors),
// created on first use; validation and synchronization validation are always on.
Context& sharedContext(ContextOptions options);

// Adds a failure for every message the layer reported to `context` since it was last asked.
void expectNoValidationMessages(Context& context);

// Fails a test whose validation messages, in any shared context, were not taken.
class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  Context& context() { return testContext(); }
};

}  // namespace smokesvd::testing
