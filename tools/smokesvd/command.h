// `smokesvd` subcommands. Each lives in its own file and registers itself:
//
//   const bool registered = cli::registerCommand({"info", [](CLI::App& app, const GlobalOptions& global,
//                                                            Action& action) { ... }});
//
// The function adds a CLI11 subcommand to `app` whose callback sets `action`; main() runs the action after
// parsing and turns any exception into a one-line error and exit status 1.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "runtime/context.h"

namespace smokesvd::cli {

// Options every subcommand shares.
struct GlobalOptions {
  std::string device;       // --device N|NAME (else SMOKESVD_DEVICE, else the best device)
  bool validation = false;      // --validation
  bool noFloatAtomics = false;  // --no-float-atomics
  bool check = false;           // --check
  ContextOptions contextOptions() const {
    ContextOptions options;
    options.device = device;
    options.validation = validation;
    options.emulateFloatAtomics = noFloatAtomics;
    options.checkFinite = check;
    return options;
  }
};

using Action = std::function<void()>;

struct Command {
  std::string name;
  std::function<void(CLI::App& app, const GlobalOptions& global, Action& action)> add;
};

// Throws Error if a command of that name is already registered (runtime/name_registry.h).
bool registerCommand(Command command);
const std::vector<Command>& commands();  // sorted by name

}  // namespace smokesvd::cli
