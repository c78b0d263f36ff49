#include "pipeline/export/export_run.h"

#include <fstream>

#include "nets/io/json_file.h"
#include "pipeline/export/mantaflow_files.h"
#include "pipeline/export/nerf_files.h"
#include "pipeline/export/vdb_files.h"
#include "pipeline/export/world_placement.h"
#include "pipeline/sim/saved_run.h"
#include "runtime/error.h"

namespace smokesvd::exporters {
namespace fs = std::filesystem;
namespace {

const char* formatName(Format format) {
  switch (format) {
    case Format::Vdb: return "vdb";
    case Format::Nerf: return "nerf";
    case Format::Mantaflow: return "mantaflow";
  }
  return "";
}

// Absent or empty: made. Holding an export: cleared with --overwrite (only the files exports write). Anything
// else: refused, untouched. A place that cannot be written: an Error before any file is.
void prepareOut(const fs::path& out, bool overwrite) {
  const std::string name = out.string();
  if (fs::exists(out)) {
    if (!fs::is_directory(out)) throw Error(name + ": exists and is not a folder");
    if (!fs::is_empty(out)) {
      std::ifstream file(out / "export.json");
      const nlohmann::json index = nlohmann::json::parse(file, nullptr, false);
      if (!index.is_object() || index.value("command", "") != "smokesvd export")
        throw Error(name + ": is not empty and holds no export; choose another --out (nothing there is touched)");
      if (!overwrite) throw Error(name + ": holds an export; --overwrite replaces it");
      for (const auto& entry : fs::directory_iterator(out)) {
        const std::string entryName = entry.path().filename().string();
        const bool exported = entryName == "export.json" || entryName == "flags.npz" || entryName.rfind("frame_", 0) == 0 ||
                              entryName.rfind("density_", 0) == 0 || entryName.rfind("velocity_", 0) == 0 ||
                              entryName.rfind("inflow_", 0) == 0;
        if (exported) fs::remove_all(entry.path());
      }
    }
  }
  try {
    fs::create_directories(out);
  } catch (const fs::filesystem_error& e) {
    throw Error(name + ": cannot create the output folder (" + e.code().message() + ")");
  }
  const fs::path probe = out / "export.json.tmp";
  if (!std::ofstream(probe)) throw Error(name + ": cannot write files there");
  fs::remove(probe);
}

}  // namespace

ExportResult runExport(const ExportOptions& o) {
  const sim::SavedRun run = sim::readSavedRun(o.source);
  if (o.format == Format::Vdb) requireOpenVdb();
  const WorldPlacement placement = placementOf(run, o.calibration, o.zUp);
  prepareOut(o.out, o.overwrite);
  nlohmann::json written;
  switch (o.format) {
    case Format::Vdb: written = writeVdb(run, placement, o.out); break;
    case Format::Nerf: written = writeNerf(run, placement, o.cameraError, o.out); break;
    case Format::Mantaflow: written = writeMantaflow(run, o.out); break;
  }
  const nlohmann::json index{{"command", "smokesvd export"},
                             {"format", formatName(o.format)},
                             {"source", fs::absolute(o.source).string()},
                             {"source_command", run.command},
                             {"frames", run.frames},
                             {"frame_rate", run.frameRate},
                             {"grid", {run.grid().x, run.grid().y, run.grid().z}},
                             {"world", placement.describe()},
                             {"written", written}};
  ExportResult result;
  result.frames = run.frames;
  result.index = o.out / "export.json";
  io::writeJsonFile(result.index, index);
  return result;
}

}  // namespace smokesvd::exporters
