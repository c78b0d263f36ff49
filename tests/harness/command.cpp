#include "tests/harness/command.h"

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "nets/io/temporary_folder.h"

namespace smokesvd::testing {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

}  // namespace

CommandResult runSmokesvd(const std::string& arguments, const std::string& environment) {
  return runCommand(environment + " " + SMOKESVD_SMOKESVD_BINARY + " " + arguments);
}

CommandResult runCommand(const std::string& shellCommand) {
  const io::TemporaryFolder directory("cli");
  const auto out = directory / "stdout";
  const auto err = directory / "stderr";
  const std::string command = shellCommand + " >" + out.string() + " 2>" + err.string() + " </dev/null";
  const int status = std::system(command.c_str());
  if (status == -1) throw std::runtime_error("could not run: " + command);
  CommandResult result;
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  result.out = slurp(out);
  result.err = slurp(err);
  return result;
}

int countLines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

}  // namespace smokesvd::testing
