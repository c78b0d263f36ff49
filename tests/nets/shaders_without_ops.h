// The shaders no registered op reaches -- simulator internals, the optimiser, tensor utilities,
// benchmarks -- each with the test that covers it. tests/nets/op_driver_test.cpp checks the table:
// every other embedded shader must be built by some op example, and every entry must name an
// embedded shader that no example reaches and a test that exists.
#pragma once

#include <string>
#include <vector>

namespace smokesvd::testing {

struct ShaderCoveredElsewhere {
  std::string shader;  // as embedded, e.g. "nn/adam"
  std::string file;    // the test source under the project root
  std::string test;    // Suite.Name of the test there that runs it
};

const std::vector<ShaderCoveredElsewhere>& shadersWithoutOps();

}  // namespace smokesvd::testing
