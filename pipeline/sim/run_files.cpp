#include "pipeline/sim/run_files.h"

#include <fstream>
#include <vector>

#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader = "# smokesvd simulate: the files this run wrote; --overwrite deletes exactly these";
// Names a run writes at its top level; a folder holding one of them without a manifest is someone else's.
const char* const kRunNames[] = {"scene.json", "flags.npz", "checkpoint.npz", "run.json", "fields", "renders"};

// A manifest line names a file inside the run: relative, without "..", not empty.
bool insideRun(const std::string& line) {
  if (line.empty() || line[0] == '#') return false;
  const fs::path path(line);
  if (path.is_absolute()) return false;
  for (const fs::path& part : path)
    if (part == "..") return false;
  return true;
}

std::vector<std::string> listedFiles(const fs::path& directory) {
  std::vector<std::string> files;
  std::ifstream manifest(directory / RunFiles::kManifest);
  std::string line;
  std::getline(manifest, line);
  while (std::getline(manifest, line))
    if (insideRun(line)) files.push_back(line);
  return files;
}

bool isEmptyFolder(const fs::path& directory) {
  std::error_code error;
  return !fs::exists(directory, error) || (fs::is_directory(directory, error) && fs::is_empty(directory, error));
}

void removeTemporariesOf(const fs::path& file) {
  std::error_code ignored;
  for (const char* suffix : {".tmp", ".tmp.mp4"}) fs::remove(file.string() + suffix, ignored);
}

}  // namespace

bool RunFiles::isRun(const fs::path& directory) {
  std::ifstream manifest(directory / kManifest);
  std::string first;
  return manifest && std::getline(manifest, first) && first == kHeader;
}

RunFiles::RunFiles(const fs::path& directory) : directory_(directory) {
  if (fs::exists(directory_) && !fs::is_directory(directory_))
    throw Error(directory_.string() + ": exists and is not a folder");
  if (isRun(directory_)) {
    for (const std::string& file : listedFiles(directory_)) listed_.insert(file);
    return;
  }
  for (const char* name : kRunNames)
    if (fs::exists(directory_ / name))
      throw Error(directory_.string() + " holds " + name + " but no " + kManifest +
                  ", so no run of smokesvd simulate wrote it; choose another --out folder (a run writes only into "
                  "a new or empty folder, or one of its own runs)");
  fs::create_directories(directory_);
  std::ofstream manifest(directory_ / kManifest);
  manifest << kHeader << "\n";
  if (!manifest) throw Error((directory_ / kManifest).string() + ": cannot write the run's manifest");
}

RunFiles RunFiles::unlisted(const fs::path& directory) {
  RunFiles files;
  files.directory_ = directory;
  files.listing_ = false;
  return files;
}

fs::path RunFiles::add(const std::string& relative) {
  if (listing_ && listed_.insert(relative).second) {
    std::ofstream manifest(directory_ / kManifest, std::ios::app);
    manifest << relative << "\n";
    manifest.flush();
    if (!manifest) throw Error((directory_ / kManifest).string() + ": cannot add " + relative + " to the run's manifest");
  }
  return directory_ / relative;
}

void RunFiles::removeTemporaries() const {
  for (const std::string& file : listed_) removeTemporariesOf(directory_ / file);
}

void RunFiles::remove(const fs::path& directory) {
  if (isEmptyFolder(directory)) return;
  if (!isRun(directory))
    throw Error(directory.string() + " is not a run of smokesvd simulate (it has no " + std::string(kManifest) +
                "); --overwrite deletes only the files a run wrote, so it refuses this folder: choose a new or "
                "empty --out folder");
  std::set<fs::path> folders;
  for (const std::string& file : listedFiles(directory)) {
    const fs::path path = directory / file;
    std::error_code ignored;
    if (!fs::is_directory(fs::symlink_status(path, ignored))) fs::remove(path, ignored);
    removeTemporariesOf(path);
    for (fs::path folder = fs::path(file).parent_path(); !folder.empty(); folder = folder.parent_path())
      folders.insert(folder);
  }
  // Deepest first; a folder that still holds something (a user's file) stays.
  for (auto it = folders.rbegin(); it != folders.rend(); ++it) {
    std::error_code ignored;
    if (fs::is_empty(directory / *it, ignored)) fs::remove(directory / *it, ignored);
  }
  // The folder stays a run, of no files yet: what a user keeps in fields/ does not make it someone else's.
  std::ofstream manifest(directory / kManifest, std::ios::trunc);
  manifest << kHeader << "\n";
  if (!manifest) throw Error((directory / kManifest).string() + ": cannot rewrite the run's manifest");
}

}  // namespace smokesvd::sim
