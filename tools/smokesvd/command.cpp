#include "tools/smokesvd/command.h"

#include "runtime/name_registry.h"

namespace smokesvd::cli {
namespace {

NameRegistry<Command>& registry() {
  static NameRegistry<Command> all("command");
  return all;
}

}  // namespace

bool registerCommand(Command command) { return registry().add(std::move(command)); }

const std::vector<Command>& commands() { return registry().all(); }

}  // namespace smokesvd::cli
