// Temporary files being written right now: the "<path>.tmp" of an atomic write (file_io.h), the
// "<path>.tmp.mp4" of a video. A process ended by SIGINT, SIGTERM or SIGHUP removes them on its way out
// once removeTemporariesOnSignals() has run (smokesvd's main() calls it), so no temporary outlives its run.
#pragma once

#include <filesystem>

namespace smokesvd::io {

// Registers `path` while the object lives (it neither creates nor deletes the file).
class InFlightTemporary {
 public:
  explicit InFlightTemporary(const std::filesystem::path& path);
  ~InFlightTemporary();
  InFlightTemporary(const InFlightTemporary&) = delete;
  InFlightTemporary& operator=(const InFlightTemporary&) = delete;

 private:
  int slot_ = -1;
};

// Unlinks every registered temporary. Async-signal-safe: it only reads the registry and calls unlink().
void removeInFlightTemporaries() noexcept;

// Handlers for SIGINT, SIGTERM and SIGHUP that remove the in-flight temporaries and then end the process
// as the signal would have; a signal ignored when this runs stays ignored.
void removeTemporariesOnSignals();

}  // namespace smokesvd::io
