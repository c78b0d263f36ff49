// Progress of a long job on stderr: on a terminal one line rewritten in place, otherwise a plain line
// every `every` updates (and at the end), so logs of CI or nohup runs stay readable.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>

namespace smokesvd {

class Progress {
 public:
  Progress(int64_t total, int64_t done, int64_t every, bool quiet);
  // Reports `done` of the total with `detail` (e.g. "loss 1.2e-03"), the rate since the start of this
  // call and the time left at that rate.
  void update(int64_t done, const std::string& detail);
  void finish();

 private:
  int64_t total_, start_, every_;
  bool quiet_, terminal_;
  bool open_ = false;
  std::chrono::steady_clock::time_point began_;
};

std::string formatDuration(double seconds);  // "1:02:03" or "2:03"

}  // namespace smokesvd
