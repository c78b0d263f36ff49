// A registry of named entries that parts of the program add themselves to from static initialisers: the
// ops of `smokesvd op` (nets/op_registry.h), the benchmarks (tools/bench/bench.h) and the commands
// (tools/smokesvd/command.h). Entries are kept sorted by their `name` member, and a name is registered once:
// adding it again throws Error ("op 'conv2d' is registered twice"). From a static initialiser that stops the
// program before main() with that message, on the first run of any build that has the clash.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "runtime/error.h"

namespace smokesvd {

template <typename Entry>
class NameRegistry {
 public:
  // `kind` names an entry in errors: "op", "benchmark", "command".
  explicit NameRegistry(std::string kind) : kind_(std::move(kind)) {}

  // Adds `entry`; throws Error if its name is already registered. Returns true, for `static const bool`.
  bool add(Entry entry) {
    const auto place = std::lower_bound(entries_.begin(), entries_.end(), entry.name,
                                        [](const Entry& e, const std::string& name) { return e.name < name; });
    if (place != entries_.end() && place->name == entry.name)
      throw Error(kind_ + " '" + entry.name + "' is registered twice");
    entries_.insert(place, std::move(entry));
    return true;
  }

  // Every entry, sorted by name.
  const std::vector<Entry>& all() const { return entries_; }

  // The entry called `name`, or nullptr.
  const Entry* find(std::string_view name) const {
    const auto place = std::lower_bound(entries_.begin(), entries_.end(), name,
                                        [](const Entry& e, std::string_view n) { return e.name < n; });
    return place != entries_.end() && place->name == name ? &*place : nullptr;
  }

 private:
  std::string kind_;
  std::vector<Entry> entries_;
};

}  // namespace smokesvd
