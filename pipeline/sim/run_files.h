// The files of one simulation run, listed in its manifest (manifest.txt) before each is first written:
// `smokesvd simulate --overwrite` deletes exactly what runs of smokesvd wrote there and nothing a user put
// beside them, and a resumed run removes the temporaries ("<file>.tmp", "<file>.tmp.mp4") an interrupted
// one left. A folder without a manifest is not a run: --overwrite refuses it, and a run does not start in
// it if it already holds a file of a run's names.
#pragma once

#include <filesystem>
#include <set>
#include <string>

namespace smokesvd::sim {

class RunFiles {
 public:
  // The run in `directory` (created if needed): its manifest is read, or started. Throws Error if the
  // folder holds files of a run's names but no manifest (another program's files, or an older run).
  explicit RunFiles(const std::filesystem::path& directory);

  const std::filesystem::path& directory() const { return directory_; }
  // directory / relative, listed in the manifest (once) before the caller writes it.
  std::filesystem::path add(const std::string& relative);
  // Deletes the temporaries of the listed files.
  void removeTemporaries() const;

  // The files of a folder another command manages itself (`smokesvd resim`): add() lists nothing.
  static RunFiles unlisted(const std::filesystem::path& directory);

  // Whether `directory` holds the manifest of a run.
  static bool isRun(const std::filesystem::path& directory);
  // Deletes every listed file and its temporaries and the folders that become empty, and empties the
  // manifest; a missing or empty folder is nothing to delete. Throws Error, deleting nothing, if the folder
  // holds anything but is not a run.
  static void remove(const std::filesystem::path& directory);

  static constexpr const char* kManifest = "manifest.txt";

 private:
  RunFiles() = default;

  std::filesystem::path directory_;
  std::set<std::string> listed_;
  bool listing_ = true;
};

}  // namespace smokesvd::sim
