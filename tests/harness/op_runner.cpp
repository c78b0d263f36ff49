#include "tests/harness/op_runner.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>

#include "tests/harness/command.h"

namespace smokesvd::testing {

OpRun runOpCommand(const std::string& op, const std::map<std::string, io::NpyArray>& inputs,
                   const std::vector<std::string>& outputs, const std::vector<std::string>& attrs) {
  static std::atomic<int> runs{0};
  namespace fs = std::filesystem;
  const fs::path folder =
      fs::temp_directory_path() / ("smokesvd-op-" + std::to_string(::getpid()) + "-" + std::to_string(runs++));
  fs::create_directories(folder);
  std::string arguments = "op " + op;
  for (const auto& [name, array] : inputs) {
    const fs::path file = folder / ("in-" + name + ".npy");
    io::writeNpy(file, array);
    arguments += " --in " + name + "=" + file.string();
  }
  for (const std::string& name : outputs) arguments += " --out " + name + "=" + (folder / (name + ".npy")).string();
  for (const std::string& attr : attrs) arguments += " --attr " + attr;

  const CommandResult result = runSmokesvd(arguments);
  OpRun run{result.exitCode, result.err, {}};
  if (result.exitCode == 0)
    for (const std::string& name : outputs) run.outputs[name] = io::readNpy(folder / (name + ".npy"));
  fs::remove_all(folder);
  return run;
}

}  // namespace smokesvd::testing
