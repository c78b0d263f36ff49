#include "tests/harness/op_runner.h"

#include "nets/io/temporary_folder.h"
#include "tests/harness/command.h"

namespace smokesvd::testing {

OpRun runOpCommand(const std::string& op, const std::map<std::string, io::NpyArray>& inputs,
                   const std::vector<std::string>& outputs, const std::vector<std::string>& attrs,
                   const std::string& globalFlags) {
  const io::TemporaryFolder folder("op");
  std::string arguments = (globalFlags.empty() ? "" : globalFlags + " ") + "op " + op;
  for (const auto& [name, array] : inputs) {
    const std::string file = folder.file("in-" + name + ".npy");
    io::writeNpy(file, array);
    arguments += " --in " + name + "=" + file;
  }
  for (const std::string& name : outputs) arguments += " --out " + name + "=" + folder.file(name + ".npy");
  for (const std::string& attr : attrs) arguments += " --attr " + attr;

  const CommandResult result = runSmokesvd(arguments);
  OpRun run{result.exitCode, result.err, {}};
  if (result.exitCode == 0)
    for (const std::string& name : outputs) run.outputs[name] = io::readNpy(folder / (name + ".npy"));
  return run;
}

}  // namespace smokesvd::testing
