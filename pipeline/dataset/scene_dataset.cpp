#include "pipeline/dataset/scene_dataset.h"

#include <algorithm>

#include "nets/io/npy.h"
#include "pipeline/sim/frame_render.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::dataset {
namespace fs = std::filesystem;
namespace {

int framesOnDisk(const fs::path& directory) {
  int frames = 0;
  while (fs::exists(directory / "fields" / ("density_" + sim::frameName(frames) + ".npz")) &&
         fs::exists(directory / "fields" / ("velocity_" + sim::frameName(frames) + ".npz")) &&
         fs::exists(directory / "fields" / ("inflow_" + sim::frameName(frames) + ".npz")))
    ++frames;
  return frames;
}

std::vector<float> readMember(const fs::path& path, const std::string& key, const Shape& expected) {
  const io::NpyArray array = io::readNpzMember(path, key);
  if (array.shape != expected)
    throw Error(path.string() + ": '" + key + "' has shape " + toString(array.shape) + ", expected " + toString(expected));
  return array.toFloat();
}

fs::path fieldPath(const SceneEntry& scene, const std::string& field, int frame) {
  if (frame < 0 || frame >= scene.frames)
    throw Error(scene.directory.string() + ": frame " + std::to_string(frame) + " outside [0, " +
                std::to_string(scene.frames) + ")");
  return scene.directory / "fields" / (field + "_" + sim::frameName(frame) + ".npz");
}

}  // namespace

SceneDataset::SceneDataset(const fs::path& root, const Preset& preset, DatasetOptions options)
    : root_(root), preset_(preset) {
  if (!fs::is_directory(root)) throw Error(root.string() + ": not a folder of simulated scenes");
  if (options.validationEvery < 2) throw Error("dataset: validation_every must be at least 2");
  std::vector<fs::path> folders;
  for (const fs::directory_entry& entry : fs::directory_iterator(root))
    if (entry.is_directory() && entry.path().filename().string().rfind("scene_", 0) == 0 &&
        fs::exists(entry.path() / "scene.json"))
      folders.push_back(entry.path());
  std::sort(folders.begin(), folders.end());
  if (folders.empty())
    throw Error(root.string() + ": no scenes (scene_NNNN/ folders with scene.json and fields/); make some with "
                "`smokesvd simulate --scenes N --preset " + preset.name + " --out " + root.string() + "`");

  for (std::size_t i = 0; i < folders.size(); ++i) {
    SceneEntry entry;
    entry.directory = folders[i];
    entry.scene = sim::readScene(folders[i] / "scene.json");
    entry.index = static_cast<int>(i);
    if (entry.scene.resolution != preset.grid)
      throw Error(folders[i].string() + ": resolution " + std::to_string(entry.scene.resolution.x) + "x" +
                  std::to_string(entry.scene.resolution.y) + "x" + std::to_string(entry.scene.resolution.z) +
                  ", but preset '" + preset.name + "' expects " + std::to_string(preset.grid.x) + "x" +
                  std::to_string(preset.grid.y) + "x" + std::to_string(preset.grid.z));
    entry.frames = framesOnDisk(folders[i]);
    if (entry.frames < options.minFrames) continue;
    const bool held = entry.index % options.validationEvery == options.validationEvery - 1;
    (held ? validation_ : training_).push_back(std::move(entry));
  }
  if (training_.empty() || validation_.empty())
    throw Error(root.string() + ": " + std::to_string(training_.size()) + " training and " +
                std::to_string(validation_.size()) + " validation scenes with at least " +
                std::to_string(options.minFrames) + " frames; both need one (every " +
                std::to_string(options.validationEvery) + "th scene is held out)");
}

float SceneDataset::densityScale(const SceneEntry& scene) const {
  return static_cast<float>(scene.scene.render.absorption / preset_.absorption);
}

std::vector<float> SceneDataset::density(const SceneEntry& scene, int frame) const {
  std::vector<float> values = readMember(fieldPath(scene, "density", frame), "density",
                                         {preset_.grid.z, preset_.grid.y, preset_.grid.x});
  const float scale = densityScale(scene);
  for (float& v : values) v *= scale;
  return values;
}

std::vector<float> SceneDataset::inflow(const SceneEntry& scene, int frame) const {
  std::vector<float> values = readMember(fieldPath(scene, "inflow", frame), "inflow",
                                         {preset_.grid.z, preset_.grid.y, preset_.grid.x});
  const float scale = densityScale(scene);
  for (float& v : values) v *= scale;
  return values;
}

std::vector<float> SceneDataset::velocity(const SceneEntry& scene, int frame) const {
  const std::vector<float> interleaved = readMember(fieldPath(scene, "velocity", frame), "velocity",
                                                    {preset_.grid.z, preset_.grid.y, preset_.grid.x, 3});
  const std::size_t cells = interleaved.size() / 3;
  std::vector<float> planar(interleaved.size());
  for (std::size_t c = 0; c < cells; ++c)
    for (std::size_t axis = 0; axis < 3; ++axis) planar[axis * cells + c] = interleaved[3 * c + axis];
  return planar;
}

std::vector<float> SceneDataset::flags(const SceneEntry& scene) const {
  return readMember(scene.directory / "flags.npz", "flags", {preset_.grid.z, preset_.grid.y, preset_.grid.x});
}

render::RenderSettings SceneDataset::look(const SceneEntry& scene) const {
  render::RenderSettings look = sim::renderSettings(scene.scene.render);
  const float scale = densityScale(scene);
  look.absorption = preset_.absorption;
  float brightness = look.ambient;
  if (look.light) {
    look.light->absorption /= scale;
    brightness += look.light->intensity;
  }
  if (!(brightness > 0)) throw Error(scene.directory.string() + ": the scene's render has no light (ambient + intensity <= 0)");
  look.ambient /= brightness;
  if (look.light) look.light->intensity /= brightness;
  return look;
}

}  // namespace smokesvd::dataset
