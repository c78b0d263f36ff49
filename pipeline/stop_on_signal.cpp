#include "pipeline/stop_on_signal.h"

#include <unistd.h>

#include "nets/io/temporary_files.h"

namespace smokesvd {
namespace {

std::atomic<bool> stopRequested{false};
std::atomic<int> stopSignal{0};

// Async-signal-safe: lock-free atomics, write(), unlink() (removeInFlightTemporaries), signal() and raise().
void onStopSignal(int signal) {
  if (stopRequested.exchange(true)) {
    io::removeInFlightTemporaries();
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  stopSignal.store(signal);
  static const char message[] = "\nsmokesvd: stopping where the run can resume; a second Ctrl-C ends it at once\n";
  const ssize_t written = ::write(STDERR_FILENO, message, sizeof message - 1);
  (void)written;
}

}  // namespace

StopOnSignal::StopOnSignal() {
  stopRequested.store(false);
  stopSignal.store(0);
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  action.sa_flags = SA_RESTART;  // the job goes on: system calls the signal interrupts are restarted
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &previousInt_);
  sigaction(SIGTERM, &action, &previousTerm_);
  // A signal the process ignores (a background job's SIGINT) stays ignored.
  if (previousInt_.sa_handler == SIG_IGN) sigaction(SIGINT, &previousInt_, nullptr);
  if (previousTerm_.sa_handler == SIG_IGN) sigaction(SIGTERM, &previousTerm_, nullptr);
}

StopOnSignal::~StopOnSignal() {
  sigaction(SIGINT, &previousInt_, nullptr);
  sigaction(SIGTERM, &previousTerm_, nullptr);
}

const std::atomic<bool>& StopOnSignal::requested() const { return stopRequested; }

void StopOnSignal::endAsSignalled() const {
  const int signal = stopSignal.load();
  if (signal == 0) return;
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

}  // namespace smokesvd
