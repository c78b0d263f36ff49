#include "pipeline/eval/fields.h"

#include "nets/io/json_file.h"
#include "nets/io/npy.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::eval {
namespace fs = std::filesystem;
namespace {

std::vector<float> readField(const fs::path& path, const std::string& key, const Shape& expected) {
  if (!fs::exists(path)) throw Error(path.string() + ": missing (expected the field '" + key + "' " + toString(expected) + ")");
  const io::NpyArray array = io::readNpzMember(path, key);
  if (array.shape != expected)
    throw Error(path.string() + ": '" + key + "' has shape " + toString(array.shape) + ", expected " + toString(expected));
  return array.toFloat();
}

fs::path fieldPath(const fs::path& folder, const std::string& field, int frame) {
  return folder / "fields" / (field + "_" + sim::frameName(frame) + ".npz");
}

Shape vectorShape(const GridSize& grid) { return {grid.z, grid.y, grid.x, 3}; }

template <typename T>
T value(const nlohmann::json& json, const std::string& pointer, const fs::path& file) {
  try {
    return json.at(nlohmann::json::json_pointer(pointer)).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw Error(file.string() + ": field '" + pointer.substr(1) + "' is missing or of the wrong type (not a run.json of smokesvd reconstruct?)");
  }
}

}  // namespace

std::vector<float> planarVelocity(const std::vector<float>& interleaved) {
  const std::size_t cells = interleaved.size() / 3;
  std::vector<float> planar(interleaved.size());
  for (std::size_t c = 0; c < cells; ++c)
    for (std::size_t axis = 0; axis < 3; ++axis) planar[axis * cells + c] = interleaved[3 * c + axis];
  return planar;
}

render::RenderSettings ReconstructionRun::look() const {
  render::RenderSettings look;
  look.absorption = absorption;
  look.ambient = 1;
  return look;
}

std::vector<float> ReconstructionRun::density(int frame) const {
  return readField(fieldPath(folder, "density", frame), "density", grid.volume());
}

std::vector<float> ReconstructionRun::velocity(int frame) const {
  return planarVelocity(readField(fieldPath(folder, "velocity", frame), "velocity", vectorShape(grid)));
}

ReconstructionRun readReconstructionRun(const fs::path& folder) {
  const fs::path runPath = folder / "run.json";
  if (!fs::is_directory(folder)) throw Error(folder.string() + ": no such folder (expected a reconstruction)");
  if (!fs::is_regular_file(runPath))
    throw Error(folder.string() + ": not a reconstruction (no run.json; make one with smokesvd reconstruct)");
  const nlohmann::json run = io::readJsonFile(runPath);
  if (run.value("command", "") != "smokesvd reconstruct")
    throw Error(folder.string() + ": not a reconstruction (its run.json was not written by smokesvd reconstruct)");
  ReconstructionRun r;
  r.folder = folder;
  r.preset = value<std::string>(run, "/preset", runPath);
  r.frames = value<int>(run, "/frames", runPath);
  if (!value<bool>(run, "/complete", runPath))
    throw Error(folder.string() + ": the reconstruction is not complete (" + std::to_string(run.value("frames_done", 0)) + " of " +
                std::to_string(r.frames) + " frames); finish it with smokesvd reconstruct --resume");
  const auto grid = value<std::vector<int64_t>>(run, "/box/grid", runPath);
  if (grid.size() != 3) throw Error(runPath.string() + ": field 'box/grid' must be [x, y, z]");
  r.grid = {.x = grid[0], .y = grid[1], .z = grid[2]};
  r.absorption = value<float>(run, "/box/absorption", runPath);
  r.firstFrame = value<std::vector<int>>(run, "/signature/frames", runPath).at(0);
  r.framing = reconstruct::parseFraming(value<std::string>(run, "/signature/framing", runPath));
  r.input = value<std::string>(run, "/signature/input", runPath);
  r.calibration = value<std::string>(run, "/signature/calibration", runPath);
  r.camera = value<std::string>(run, "/signature/camera", runPath);
  if (r.camera.empty()) r.camera = r.input.filename().string();
  const auto size = value<std::vector<int>>(run, "/signature/source/source_size", runPath);
  r.sourceWidth = size.at(0);
  r.sourceHeight = size.at(1);
  r.region = {value<double>(run, "/signature/source/region/x0", runPath), value<double>(run, "/signature/source/region/y0", runPath),
              value<double>(run, "/signature/source/region/width", runPath),
              value<double>(run, "/signature/source/region/height", runPath)};
  r.mapping.black = value<float>(run, "/signature/source/intensity/black", runPath);
  r.mapping.gain = value<float>(run, "/signature/source/intensity/gain", runPath);
  r.mapping.threshold = value<float>(run, "/signature/source/intensity/threshold", runPath);
  r.mapping.perPixelBackground = value<std::string>(run, "/signature/source/intensity/background", runPath) != "level";
  r.models = run.at("signature").value("models", nlohmann::json::object());
  for (int t = 0; t < r.frames; ++t)
    for (const char* field : {"density", "velocity"})
      if (!fs::exists(fieldPath(folder, field, t)))
        throw Error(fieldPath(folder, field, t).string() + ": missing (the reconstruction has " + std::to_string(r.frames) + " frames)");
  return r;
}

std::vector<float> TruthScene::density(int frame, float absorption) const {
  std::vector<float> values = readField(fieldPath(folder, "density", frame), "density", scene.resolution.volume());
  const float scale = static_cast<float>(scene.render.absorption / absorption);
  for (float& v : values) v *= scale;
  return values;
}

std::vector<float> TruthScene::velocity(int frame) const {
  return planarVelocity(readField(fieldPath(folder, "velocity", frame), "velocity", vectorShape(scene.resolution)));
}

TruthScene readTruthScene(const fs::path& folder) {
  if (!fs::exists(folder / "scene.json"))
    throw Error(folder.string() + ": not a simulated scene (no scene.json; make one with smokesvd simulate)");
  TruthScene truth;
  truth.folder = folder;
  truth.scene = sim::readScene(folder / "scene.json");
  while (fs::exists(fieldPath(folder, "density", truth.frames)) && fs::exists(fieldPath(folder, "velocity", truth.frames)))
    ++truth.frames;
  if (truth.frames == 0) throw Error(folder.string() + ": no fields (fields/density_0000.npz and velocity_0000.npz)");
  return truth;
}

}  // namespace smokesvd::eval
