#include "tests/harness/temp_dir.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace smokesvd::testing {

TempDir::TempDir(const std::string& purpose) : TempDir(purpose, std::filesystem::temp_directory_path()) {}

std::filesystem::path TempDir::memoryBacked() {
  std::error_code error;
  if (std::filesystem::is_directory("/dev/shm", error) && ::access("/dev/shm", W_OK) == 0) return "/dev/shm";
  return std::filesystem::temp_directory_path();
}

TempDir::TempDir(const std::string& purpose, const std::filesystem::path& parent) {
  const std::string pattern = (parent / ("smokesvd-" + purpose + "-XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (::mkdtemp(name.data()) == nullptr)
    throw std::runtime_error("cannot create a temporary folder " + pattern + ": " + std::strerror(errno));
  path_ = name.data();
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace smokesvd::testing
