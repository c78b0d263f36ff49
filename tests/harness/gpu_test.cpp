#include "tests/harness/gpu_test.h"

#include <map>
#include <memory>
#include <tuple>

namespace smokesvd::testing {
namespace {

using ContextKey = std::tuple<std::string, bool, bool, bool>;

std::map<ContextKey, std::unique_ptr<Context>>& sharedContexts() {
  static std::map<ContextKey, std::unique_ptr<Context>> contexts;
  return contexts;
}

// After the last test: destroys the shared contexts and fails the run on any message the layer raised
// since the tests last looked, in teardown, or in contexts the tests made and destroyed themselves.
class ValidationAfterTheTests : public ::testing::Environment {
 public:
  void TearDown() override {
    for (auto& [key, context] : sharedContexts()) expectNoValidationMessages(*context);
    sharedContexts().clear();
    for (const std::string& message : Context::takeUnreadValidationMessages())
      ADD_FAILURE() << "validation layer, outside any test (context teardown or a test's own context): " << message;
  }
};

[[maybe_unused]] const ::testing::Environment* const registered =
    ::testing::AddGlobalTestEnvironment(new ValidationAfterTheTests);

}  // namespace

Context& sharedContext(ContextOptions options) {
  options.validation = true;
  options.synchronizationValidation = true;
  const ContextKey key{options.device, options.forceStaging, options.emulateFloatAtomics, options.guardTensors};
  std::unique_ptr<Context>& context = sharedContexts()[key];
  if (!context) context = std::make_unique<Context>(options);
  return *context;
}

Context& testContext() { return sharedContext({.guardTensors = true}); }

Context& unguardedTestContext() { return sharedContext({}); }

void expectNoValidationMessages(Context& context) {
  for (const std::string& message : context.takeValidationMessages()) ADD_FAILURE() << "validation layer: " << message;
}

void GpuTest::SetUp() {
  testContext();
  for (auto& [key, context] : sharedContexts())
    for (const std::string& message : context->takeValidationMessages())
      ADD_FAILURE() << "validation message before the test: " << message;
}

void GpuTest::TearDown() {
  for (auto& [key, context] : sharedContexts()) expectNoValidationMessages(*context);
}

}  // namespace smokesvd::testing
