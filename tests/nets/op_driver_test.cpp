// The registry-driven op test: every example of every registered op (nets/op_example.h), run
//   - directly into NaN-poisoned tensors with guard regions (ContextOptions::guardTensors): every
//     output and gradient finite, no guard written, forward with and without gradients agreeing;
//   - backward against central differences of the op's own forward (ops with a backward);
//   - through `smokesvd op`: the same outputs and gradients, bit for bit unless the example allows
//     atomics' reordering (OpExample::repeatTolerance); an op without a backward refuses a gradient.
// And the coverage: every op has an example, and every embedded shader is built by some example or
// listed in tests/nets/shaders_without_ops.cpp with the test that covers it.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "nets/op_registry.h"
#include "runtime/context.h"
#include "runtime/embedded_shaders.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_driver.h"
#include "tests/nets/shaders_without_ops.h"

namespace smokesvd::testing {
namespace {

ContextOptions options(bool noFloatAtomics, bool guarded) {
  ContextOptions o;
  o.validation = true;
  o.emulateFloatAtomics = noFloatAtomics;
  o.guardTensors = guarded;
  return o;
}

// One guarded context per atomics mode, shared by the process (tests/harness/gpu_test.h).
Context& guardedContext(bool noFloatAtomics) { return sharedContext(options(noFloatAtomics, true)); }

std::vector<std::string> opNames() {
  std::vector<std::string> names;
  for (const OpSpec& spec : registeredOps()) names.push_back(spec.name);
  return names;
}

class OpDriver : public ::testing::TestWithParam<std::string> {};

TEST_P(OpDriver, EveryExample) {
  const OpSpec& spec = findOp(GetParam());
  ASSERT_FALSE(spec.examples.empty()) << "op " << spec.name << " registers no example (nets/op_example.h)";
  const bool differentiable = spec.differentiable == Differentiable::Yes;
  for (const OpExample& example : spec.examples) {
    SCOPED_TRACE("op " + spec.name + ", example '" + example.name + "'");
    Context& context = guardedContext(example.noFloatAtomics);
    const NamedTensors inputs = drawInputs(example);

    const OpResult forward = runDirect(context, spec, example, inputs, nullptr);
    EXPECT_TRUE(allFinite(forward)) << "forward only";
    EXPECT_TRUE(guardsIntact(forward)) << "forward only";
    std::string failure;
    if (!differentiable) {
      EXPECT_TRUE(sameResults(forward, runThroughCli(spec, example, inputs, nullptr, &failure), 0)) << failure;
      const NamedTensors seeds = drawSeeds(forward.outputs, example.seed);
      failure.clear();
      runThroughCli(spec, example, inputs, &seeds, &failure);
      EXPECT_NE(failure.find("smokesvd: error:"), std::string::npos)
          << "an op without a backward must refuse an upstream gradient; got " << failure;
      continue;
    }

    const NamedTensors seeds = drawSeeds(forward.outputs, example.seed);
    const OpResult both = runDirect(context, spec, example, inputs, &seeds);
    EXPECT_TRUE(allFinite(both)) << "forward and backward";
    EXPECT_TRUE(guardsIntact(both)) << "forward and backward";
    EXPECT_TRUE(sameResults(forward, OpResult{both.outputs, {}}, 1e-5))
        << "the forward with gradients differs from the forward without";
    EXPECT_TRUE(gradientsMatchDifferences(context, spec, example, inputs, seeds, both));
    EXPECT_TRUE(sameResults(both, runThroughCli(spec, example, inputs, &seeds, &failure), example.repeatTolerance))
        << "smokesvd op " << spec.name << " " << failure;
  }
  for (const OpExample& example : spec.examples) expectNoValidationMessages(guardedContext(example.noFloatAtomics));
}

INSTANTIATE_TEST_SUITE_P(Registry, OpDriver, ::testing::ValuesIn(opNames()),
                         [](const ::testing::TestParamInfo<std::string>& op) { return op.param; });

TEST(OpDriverCoverage, EveryOpHasAnExample) {
  for (const OpSpec& spec : registeredOps()) {
    EXPECT_FALSE(spec.examples.empty()) << "op " << spec.name << " registers no example (nets/op_example.h)";
    std::set<std::string> names;
    for (const OpExample& example : spec.examples)
      EXPECT_TRUE(names.insert(example.name).second) << "op " << spec.name << ": two examples named '" << example.name << "'";
  }
}

// Runs every example once (forward, and forward and backward), in fresh contexts, and collects the
// shaders they built.
std::set<std::string> shadersReachedByOps() {
  std::set<std::string> reached;
  for (bool noFloatAtomics : {false, true}) {
    Context context(options(noFloatAtomics, false));
    for (const OpSpec& spec : registeredOps())
      for (const OpExample& example : spec.examples) {
        if (example.noFloatAtomics != noFloatAtomics) continue;
        const NamedTensors inputs = drawInputs(example);
        const OpResult forward = runDirect(context, spec, example, inputs, nullptr);
        if (spec.differentiable == Differentiable::Yes) {
          const NamedTensors seeds = drawSeeds(forward.outputs, example.seed);
          runDirect(context, spec, example, inputs, &seeds);
        }
      }
    for (const std::string& shader : context.builtShaders()) reached.insert(shader);
    expectNoValidationMessages(context);
  }
  return reached;
}

bool fileMentions(const std::string& path, const std::string& test) {
  std::ifstream file(std::filesystem::path(SMOKESVD_SOURCE_DIR) / path);
  if (!file) return false;
  std::stringstream text;
  text << file.rdbuf();
  const std::size_t dot = test.find('.');
  const std::string suite = test.substr(0, dot), name = dot == std::string::npos ? "" : test.substr(dot + 1);
  return text.str().find(suite) != std::string::npos && text.str().find(name) != std::string::npos;
}

TEST(OpDriverCoverage, EveryShaderIsReachedByAnOpOrListed) {
  const std::set<std::string> reached = shadersReachedByOps();
  std::map<std::string, const ShaderCoveredElsewhere*> listed;
  for (const ShaderCoveredElsewhere& entry : shadersWithoutOps()) {
    EXPECT_TRUE(listed.emplace(entry.shader, &entry).second) << entry.shader << " is listed twice";
    EXPECT_TRUE(embeddedShaders().count(entry.shader))
        << entry.shader << " is listed in tests/nets/shaders_without_ops.cpp but no such shader is embedded";
    EXPECT_FALSE(reached.count(entry.shader))
        << entry.shader << " is reached by an op's example: remove it from tests/nets/shaders_without_ops.cpp";
    EXPECT_TRUE(fileMentions(entry.file, entry.test))
        << entry.shader << ": the covering test " << entry.test << " is not in " << entry.file;
  }
  for (const auto& [shader, spirv] : embeddedShaders())
    EXPECT_TRUE(reached.count(shader) || listed.count(shader))
        << "no op example reaches shader " << shader
        << ": register an example that does (nets/op_example.h), or list the test that covers it in "
           "tests/nets/shaders_without_ops.cpp";
}

}  // namespace
}  // namespace smokesvd::testing
