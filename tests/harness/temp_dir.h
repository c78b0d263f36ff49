// A fresh folder for one test's files, removed with everything in it when the object goes. Names are
// unique (mkdtemp), so tests running at once -- in parallel ctest jobs or in two checkouts -- never
// share one.
#pragma once

#include <filesystem>
#include <string>

namespace smokesvd::testing {

class TempDir {
 public:
  // Under the system's temporary directory, named smokesvd-<purpose>-XXXXXX.
  explicit TempDir(const std::string& purpose = "test");
  // Under `parent` instead.
  TempDir(const std::string& purpose, const std::filesystem::path& parent);
  // /dev/shm where it exists (memory: thousands of small files in seconds), else the temporary directory.
  static std::filesystem::path memoryBacked();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // The path of `name` inside the folder, as a string for command lines.
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace smokesvd::testing
