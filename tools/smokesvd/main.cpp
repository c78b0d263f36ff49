// smokesvd: single-view smoke reconstruction on Vulkan compute. Parses the command line, runs the chosen
// subcommand, and turns any failure into one line on stderr, `smokesvd: error: ...`, and a non-zero exit
// status: 2 when the command line is not understood, 1 when the command fails (or when the validation
// layer, with --validation, reported anything, even while the last context was being destroyed).
#include <iostream>
#include <new>

#include "nets/io/temporary_files.h"
#include "runtime/context.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"

namespace {

using namespace smokesvd;

constexpr int kFailed = 1;
constexpr int kBadCommandLine = 2;

// Newlines and runs of blanks become one space, so that every error is one line.
std::string oneLine(const std::string& text) {
  std::string line;
  for (char c : text) {
    const bool blank = c == '\n' || c == '\r' || c == '\t' || c == ' ';
    if (blank && (line.empty() || line.back() == ' ')) continue;
    line += blank ? ' ' : c;
  }
  while (!line.empty() && line.back() == ' ') line.pop_back();
  return line;
}

int fail(const std::string& message, int status) {
  std::cerr << "smokesvd: error: " << oneLine(message) << "\n";
  return status;
}

// The first argument that is not an option (nor the value of --device), which must name a command: CLI11
// would otherwise take `smokesvd eval --help` for a request of the main help.
const char* commandWord(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--device") ++i;
    else if (!argument.starts_with("-")) return argv[i];
  }
  return nullptr;
}

bool isCommand(const std::string& word) {
  for (const cli::Command& command : cli::commands())
    if (command.name == word) return true;
  return false;
}

std::string commandNames() {
  std::string names;
  for (const cli::Command& command : cli::commands()) names += (names.empty() ? "" : ", ") + command.name;
  return names;
}

// The command line was understood but running it failed, or the validation layer spoke.
int runAction(const cli::Action& action) {
  std::string failure;
  try {
    action();
  } catch (const std::bad_alloc&) {
    failure = "out of host memory";
  } catch (const std::exception& error) {
    failure = error.what();
  }
  const std::vector<std::string> messages = Context::takeUnreadValidationMessages();
  if (!messages.empty())
    failure += (failure.empty() ? "" : "; and ") + std::string("the Vulkan validation layer reported ") +
               std::to_string(messages.size()) + (messages.size() == 1 ? " message: " : " messages, the first: ") +
               messages.front();
  return failure.empty() ? 0 : fail(failure, kFailed);
}

}  // namespace

int main(int argc, char** argv) {
  io::removeTemporariesOnSignals();  // Ctrl-C or a kill leaves no half-written "<file>.tmp" behind
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
  if (const char* word = commandWord(argc, argv); word != nullptr && !isCommand(word))
    return fail(std::string("unknown command '") + word + "'; the commands are " + commandNames() +
                    " (smokesvd --help describes them)",
                kBadCommandLine);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& help) {
    return app.exit(help);  // --help: the help of the command given, on stdout
  } catch (const CLI::ParseError& error) {
    const CLI::App* command = app.get_subcommands().empty() ? nullptr : app.get_subcommands().front();
    return fail(std::string(error.what()) + " (see smokesvd " + (command ? command->get_name() + " " : "") + "--help)",
                kBadCommandLine);
  }
  return runAction(action);
}
