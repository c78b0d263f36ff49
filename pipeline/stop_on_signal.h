// Ctrl-C during a long job that can resume: the first SIGINT or SIGTERM asks the job to stop at the next
// point it can resume from (training: its next log step, after writing a checkpoint there) instead of
// ending the process and losing the work since the last checkpoint; a second one ends the process at
// once, as the signal would, with the in-flight temporaries removed (nets/io/temporary_files.h). The
// handlers are installed while the object lives; the ones before them are put back afterwards. One at a
// time: the request is the process's. A signal the process ignores (SIGINT of a background job) stays ignored.
#pragma once

#include <atomic>
#include <csignal>

namespace smokesvd {

class StopOnSignal {
 public:
  StopOnSignal();
  ~StopOnSignal();
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

  // Becomes true on the first signal.
  const std::atomic<bool>& requested() const;
  // Once the job has stopped: ends the process as the signal that asked would have (a shell running it
  // sees it interrupted, so a script of several jobs stops too). Does nothing if no signal came.
  void endAsSignalled() const;

 private:
  struct sigaction previousInt_ {}, previousTerm_ {};
};

}  // namespace smokesvd
