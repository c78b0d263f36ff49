#include "nets/io/temporary_files.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace smokesvd::io {
namespace {

// A fixed table, so that a signal handler can walk it without locks or allocation. A slot is free (0),
// being filled (1) or holds a path (2).
constexpr int kSlots = 64;
constexpr std::size_t kPathBytes = 4096;

struct Slot {
  std::atomic<int> state{0};
  char path[kPathBytes];
};

Slot slots[kSlots];

void onSignal(int signal) {
  removeInFlightTemporaries();
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace

InFlightTemporary::InFlightTemporary(const std::filesystem::path& path) {
  const std::string& text = path.native();
  if (text.size() >= kPathBytes) return;  // not removable on a signal; the next resume still finds it
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(slots[i].path, text.c_str(), text.size() + 1);
    slots[i].state.store(2);
    slot_ = i;
    return;
  }
}

InFlightTemporary::~InFlightTemporary() {
  if (slot_ >= 0) slots[slot_].state.store(0);
}

void removeInFlightTemporaries() noexcept {
  for (Slot& slot : slots)
    if (slot.state.load() == 2) ::unlink(slot.path);
}

void removeTemporariesOnSignals() {
  // A signal the process was started ignoring (SIGINT and SIGHUP of a job in the background, under nohup)
  // stays ignored.
  for (int signal : {SIGINT, SIGTERM, SIGHUP})
    if (std::signal(signal, onSignal) == SIG_IGN) std::signal(signal, SIG_IGN);
}

}  // namespace smokesvd::io
