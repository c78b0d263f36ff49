// Runs the `smokesvd` binary as a user would (or any shell command), capturing exit status, stdout and stderr.
#pragma once

#include <string>

namespace smokesvd::testing {

struct CommandResult {
  int exitCode = -1;
  std::string out;
  std::string err;
};

// `arguments` are appended to the smokesvd binary's path; `environment` (e.g. "VK_DRIVER_FILES=/x")
// is prefixed to the shell command.
CommandResult runSmokesvd(const std::string& arguments, const std::string& environment = "");

// Runs `command` through the shell with stdin from /dev/null.
CommandResult runCommand(const std::string& command);

// The number of '\n' in `text`: a one-line error is countLines(err) == 1.
int countLines(const std::string& text);

}  // namespace smokesvd::testing
