#include "nets/io/temporary_folder.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "runtime/error.h"

namespace smokesvd::io {

TemporaryFolder::TemporaryFolder(const std::string& purpose)
    : TemporaryFolder(purpose, std::filesystem::temp_directory_path()) {}

std::filesystem::path TemporaryFolder::memoryBacked() {
  std::error_code error;
  if (std::filesystem::is_directory("/dev/shm", error) && ::access("/dev/shm", W_OK) == 0) return "/dev/shm";
  return std::filesystem::temp_directory_path();
}

TemporaryFolder::TemporaryFolder(const std::string& purpose, const std::filesystem::path& parent) {
  const std::string pattern = (parent / ("smokesvd-" + purpose + "-XXXXXX")).string();
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  if (::mkdtemp(name.data()) == nullptr)
    throw Error(pattern + ": cannot create a temporary folder: " + std::strerror(errno));
  path_ = name.data();
}

TemporaryFolder::~TemporaryFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace smokesvd::io
