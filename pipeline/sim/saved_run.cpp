#include "pipeline/sim/saved_run.h"

#include <fstream>

#include "nets/io/npy.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::sim {
namespace fs = std::filesystem;
namespace {

std::vector<float> planarFromInterleaved(const std::vector<float>& interleaved) {
  const std::size_t cells = interleaved.size() / 3;
  std::vector<float> planar(interleaved.size());
  for (std::size_t c = 0; c < cells; ++c)
    for (std::size_t a = 0; a < 3; ++a) planar[a * cells + c] = interleaved[3 * c + a];
  return planar;
}

// The calibration a run's box was placed with: a reconstruction of calibrated footage records it in its
// signature, a re-simulation copies its source's.
std::optional<fs::path> recordedCalibration(const nlohmann::json& run) {
  const nlohmann::json signature = run.value("signature", nlohmann::json::object());
  if (signature.value("framing", "") == "calibrated" && signature.contains("calibration"))
    return fs::path(signature["calibration"].get<std::string>());
  if (run.contains("calibration") && run["calibration"].is_string()) return fs::path(run["calibration"].get<std::string>());
  return std::nullopt;
}

double recordedFrameRate(const nlohmann::json& run) {
  const nlohmann::json source = run.value("signature", nlohmann::json::object()).value("source", nlohmann::json::object());
  const double rate = source.value("frame_rate", run.value("frame_rate", 30.0));
  return rate > 0 ? rate : 30.0;
}

}  // namespace

fs::path SavedRun::field(const std::string& name, int frame) const {
  return root / "fields" / (name + "_" + frameName(frame) + ".npz");
}

std::vector<float> SavedRun::density(int frame) const {
  const io::NpyArray array = io::readNpzMember(field("density", frame), "density");
  if (array.shape != grid().volume())
    throw Error(field("density", frame).string() + ": shape " + toString(array.shape) + ", scene.json says " +
                toString(grid().volume()));
  return array.toFloat();
}

std::vector<float> SavedRun::inflow(int frame) const {
  const io::NpyArray array = io::readNpzMember(field("inflow", frame), "inflow");
  if (array.shape != grid().volume())
    throw Error(field("inflow", frame).string() + ": shape " + toString(array.shape) + ", scene.json says " +
                toString(grid().volume()));
  return array.toFloat();
}

std::vector<float> SavedRun::velocity(int frame) const {
  const io::NpyArray array = io::readNpzMember(field("velocity", frame), "velocity");
  const Shape expected{grid().z, grid().y, grid().x, 3};
  if (array.shape != expected)
    throw Error(field("velocity", frame).string() + ": shape " + toString(array.shape) + ", scene.json says " +
                toString(expected));
  return planarFromInterleaved(array.toFloat());
}

SavedRun readSavedRun(const fs::path& root) {
  const std::string name = root.string();
  if (!fs::is_directory(root)) throw Error(name + ": no such folder");
  const fs::path runPath = root / "run.json";
  if (!fs::exists(runPath) || !fs::exists(root / "scene.json"))
    throw Error(name + ": not a run folder (no run.json and scene.json; expected the output of smokesvd reconstruct, resim or simulate)");
  SavedRun saved;
  saved.root = root;
  std::ifstream file(runPath);
  saved.run = nlohmann::json::parse(file, nullptr, false);
  if (!saved.run.is_object()) throw Error(runPath.string() + ": not valid JSON");
  saved.command = saved.run.value("command", "smokesvd simulate");
  if (!saved.run.value("complete", false))
    throw Error(name + ": the run is not complete (run.json says so); finish it first");
  saved.scene = readScene(root / "scene.json");
  saved.frames = saved.run.value("frames", 0);
  if (saved.frames < 1) throw Error(runPath.string() + ": field 'frames': expected a frame count >= 1");
  for (int t = 0; t < saved.frames; ++t)
    for (const char* f : {"density", "velocity", "inflow"})
      if (!fs::exists(saved.field(f, t))) throw Error(name + ": " + saved.field(f, t).filename().string() + " is missing");
  saved.frameRate = recordedFrameRate(saved.run);
  saved.calibration = recordedCalibration(saved.run);
  return saved;
}

}  // namespace smokesvd::sim
