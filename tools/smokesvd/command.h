// Each `smokesvd` subcommand lives in its own file and adds itself to the CLI11 app here.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "runtime/context.h"

namespace smokesvd::cli {

// Options every subcommand shares.
struct GlobalOptions {
  std::string device;       // --device N|NAME (else SMOKESVD_DEVICE, else the best device)
  bool validation = false;  // --validation
  ContextOptions contextOptions() const { return {device, validation}; }
};

// A subcommand's action runs after parsing; errors thrown from it become the one-line message.
using Action = std::function<void()>;

void addInfoCommand(CLI::App& app, const GlobalOptions& global, Action& action);
void addBenchCommand(CLI::App& app, const GlobalOptions& global, Action& action);

}  // namespace smokesvd::cli
