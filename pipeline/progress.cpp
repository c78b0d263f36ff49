#include "pipeline/progress.h"

#include <cstdio>

#include <unistd.h>

namespace smokesvd {

std::string formatDuration(double seconds) {
  const auto total = static_cast<int64_t>(seconds + 0.5);
  char text[32];
  if (total >= 3600)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", static_cast<long long>(total / 3600),
                  static_cast<long long>(total / 60 % 60), static_cast<long long>(total % 60));
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", static_cast<long long>(total / 60), static_cast<long long>(total % 60));
  return text;
}

Progress::Progress(int64_t total, int64_t done, int64_t every, bool quiet)
    : total_(total), start_(done), every_(every > 0 ? every : 1), quiet_(quiet),
      terminal_(isatty(fileno(stderr)) != 0), began_(std::chrono::steady_clock::now()) {}

void Progress::update(int64_t done, const std::string& detail) {
  if (quiet_) return;
  if (!terminal_ && done % every_ != 0 && done != total_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - began_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done - start_) / elapsed : 0.0;
  const double left = rate > 0 ? static_cast<double>(total_ - done) / rate : 0.0;
  const int width = 24;
  const int filled = total_ > 0 ? static_cast<int>(width * done / total_) : width;
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "%s[%s] %lld/%lld  %s  %.2f/s  ETA %s%s", terminal_ ? "\r" : "", bar.c_str(),
               static_cast<long long>(done), static_cast<long long>(total_), detail.c_str(), rate,
               formatDuration(left).c_str(), terminal_ ? "\033[K" : "\n");
  std::fflush(stderr);
  open_ = terminal_;
}

void Progress::finish() {
  if (open_) std::fputc('\n', stderr);
  open_ = false;
}

}  // namespace smokesvd
