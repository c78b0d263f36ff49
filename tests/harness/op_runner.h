// Runs one registered op through `smokesvd op` as a user would: inputs (and grad_* upstream gradients)
// are written to .npy files in a fresh temporary folder, the named outputs (and grad_* input gradients)
// are read back. Every test that runs an op on the command line goes through here.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "nets/io/npy.h"

namespace smokesvd::testing {

struct OpRun {
  int exitCode = -1;
  std::string err;
  std::map<std::string, io::NpyArray> outputs;  // those asked for, when the command succeeded
};

// `attrs` are NAME=VALUE pairs passed as --attr; `globalFlags` go before `op` (e.g. "--no-float-atomics").
OpRun runOpCommand(const std::string& op, const std::map<std::string, io::NpyArray>& inputs,
                   const std::vector<std::string>& outputs, const std::vector<std::string>& attrs = {},
                   const std::string& globalFlags = "");

}  // namespace smokesvd::testing
