// smokesvd: single-view smoke reconstruction on Vulkan compute. Parses the command line, runs the chosen
// subcommand, and turns any failure into one line on stderr and a non-zero exit status.
#include <iostream>

#include "runtime/error.h"
#include "tools/smokesvd/command.h"

int main(int argc, char** argv) {
  using namespace smokesvd;
  CLI::App app{"smokesvd: single-view smoke reconstruction (density, velocity, re-simulation) on Vulkan compute"};
  app.require_subcommand(1);
  cli::GlobalOptions global;
  app.add_option("--device", global.device, "Vulkan device: index or name substring (default: best; env SMOKESVD_DEVICE)");
  app.add_flag("--validation", global.validation, "enable the Khronos validation layer (env SMOKESVD_VALIDATION=1)");
  app.add_flag("--no-float-atomics", global.noFloatAtomics,
               "scatter gradients with compare-and-swap loops, as on a device without float32 atomic add");
  app.add_flag("--check", global.check,
               "scan what every kernel writes for NaN/Inf and stop at the first, naming the shader, binding and "
               "element (slow; env SMOKESVD_CHECK=1)");
  cli::Action action;
  for (const cli::Command& command : cli::commands()) command.add(app, global, action);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  }
  try {
    action();
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "smokesvd: error: " << error.what() << "\n";
    return 1;
  }
}
