// The pieces of the registry-driven op test (tests/nets/op_driver_test.cpp): an op's registered
// examples (nets/op_example.h) drawn, run directly and through `smokesvd op`, and checked.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "nets/op_registry.h"
#include "runtime/context.h"

namespace smokesvd::testing {

struct HostTensor {
  Shape shape;
  std::vector<float> values;
};
using NamedTensors = std::map<std::string, HostTensor>;

// The example's inputs, drawn with its seed, by input name.
NamedTensors drawInputs(const OpExample& example);
// One upstream gradient per output, uniform in [-1, 1), by output name.
NamedTensors drawSeeds(const NamedTensors& outputs, uint64_t seed);

struct OpResult {
  NamedTensors outputs;    // by output name
  NamedTensors gradients;  // "grad_<input>" of every given input, when upstream gradients were given
  // In a guarded context (ContextOptions::guardTensors): every tensor of the run whose guard a kernel
  // wrote, checked after the run while the stream still holds them all.
  std::vector<std::string> guardViolations;
};

// spec.apply in `context`, as `smokesvd op` runs it: with `seeds` every given input requires a gradient
// and the backward runs from them; without, forward only.
OpResult runDirect(Context& context, const OpSpec& spec, const OpExample& example, const NamedTensors& inputs,
                   const NamedTensors* seeds);
// The same call through `smokesvd op` (the CLI's exit status and message in `failure` if it failed).
OpResult runThroughCli(const OpSpec& spec, const OpExample& example, const NamedTensors& inputs,
                       const NamedTensors* seeds, std::string* failure);

// Every element of every tensor is finite (a NaN is an element no kernel wrote: runs are poisoned).
::testing::AssertionResult allFinite(const OpResult& result);
// No kernel of the run wrote past the end of a tensor.
::testing::AssertionResult guardsIntact(const OpResult& result);
// Same names, shapes and values: bit for bit when `relative` is 0, else within relative times the
// largest magnitude of each tensor.
::testing::AssertionResult sameResults(const OpResult& expected, const OpResult& actual, double relative);
// The backward of `withGradients` against central differences of the op's own forward in `context`
// (probes and tolerances: GradientCheck in nets/op_example.h).
::testing::AssertionResult gradientsMatchDifferences(Context& context, const OpSpec& spec, const OpExample& example,
                                                     const NamedTensors& inputs, const NamedTensors& seeds,
                                                     const OpResult& withGradients);

}  // namespace smokesvd::testing
