// Base fixture for every test that touches the GPU: one Context per test process, created with the
// Khronos validation layer on; a test fails if the layer reported anything while it ran.
#pragma once

#include <gtest/gtest.h>

#include "runtime/context.h"

namespace smokesvd::testing {

// The process-wide validated context (created on first use).
Context& testContext();

class GpuTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  Context& context() { return testContext(); }
};

}  // namespace smokesvd::testing
