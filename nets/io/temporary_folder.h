// A fresh folder for scratch files, removed with everything in it when the object goes. Names are unique
// (mkdtemp), so programs running at once -- parallel test jobs, two benchmarks, two checkouts -- never
// share one. Used by the benchmarks' scratch scenes and by every test that writes files.
#pragma once

#include <filesystem>
#include <string>

namespace smokesvd::io {

class TemporaryFolder {
 public:
  // Under the system's temporary directory, named smokesvd-<purpose>-XXXXXX.
  explicit TemporaryFolder(const std::string& purpose = "scratch");
  // Under `parent` instead.
  TemporaryFolder(const std::string& purpose, const std::filesystem::path& parent);
  // /dev/shm where it exists (memory: thousands of small files in seconds), else the temporary directory.
  static std::filesystem::path memoryBacked();
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  // The path of `name` inside the folder, as a string for command lines.
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace smokesvd::io
