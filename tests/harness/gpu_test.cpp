#include "tests/harness/gpu_test.h"

#include <memory>

namespace smokesvd::testing {

Context& testContext() {
  static std::unique_ptr<Context> context = [] {
    ContextOptions options;
    options.validation = true;
    return std::make_unique<Context>(options);
  }();
  return *context;
}

void GpuTest::SetUp() {
  for (const std::string& message : testContext().takeValidationMessages())
    ADD_FAILURE() << "validation message before the test: " << message;
}

void GpuTest::TearDown() {
  for (const std::string& message : testContext().takeValidationMessages())
    ADD_FAILURE() << "validation layer: " << message;
}

}  // namespace smokesvd::testing
