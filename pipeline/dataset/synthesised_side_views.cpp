#include "pipeline/dataset/synthesised_side_views.h"

#include <algorithm>

#include "nets/io/json_file.h"
#include "nets/io/npy.h"
#include "runtime/error.h"

namespace smokesvd::dataset {
namespace fs = std::filesystem;
namespace {

const char* kManifest = "rollout.json";

fs::path sceneFile(const fs::path& folder, const SceneEntry& scene) {
  return folder / (scene.directory.filename().string() + ".npy");
}

SideViewRolloutManifest manifestFromJson(const nlohmann::json& j, const fs::path& path) {
  SideViewRolloutManifest m;
  try {
    m.preset = j.at("preset").get<std::string>();
    m.firstFrame = j.at("first_frame").get<int>();
    m.frames = j.at("frames").get<int>();
    m.height = j.at("image").at(0).get<int>();
    m.width = j.at("image").at(1).get<int>();
    m.how = {{"history", j.at("history")}, {"sampling", j.at("sampling")}};
  } catch (const nlohmann::json::exception& e) {
    throw Error(path.string() + ": not a side-view rollout's manifest (" + e.what() +
                "); expected preset, first_frame, frames, image [h, w], history and sampling");
  }
  return m;
}

}  // namespace

nlohmann::json SideViewRolloutManifest::toJson() const {
  nlohmann::json j = {{"preset", preset}, {"first_frame", firstFrame}, {"frames", frames}, {"image", {height, width}}};
  for (const auto& [key, value] : how.items()) j[key] = value;
  return j;
}

void prepareSideViewFolder(const fs::path& folder, const SideViewRolloutManifest& manifest) {
  const fs::path path = folder / kManifest;
  if (!fs::exists(path)) {
    fs::create_directories(folder);
    io::writeJsonFile(path, manifest.toJson());
    return;
  }
  const nlohmann::json there = io::readJsonFile(path), here = manifest.toJson();
  for (const auto& [key, value] : here.items())
    if (!there.contains(key) || there[key] != value)
      throw Error(path.string() + ": '" + key + "' is " + (there.contains(key) ? there[key].dump() : "missing") +
                  " there and " + value.dump() + " in this rollout; keep its side views in another folder");
}

std::optional<std::vector<float>> readSceneSideViews(const fs::path& folder, const SideViewRolloutManifest& manifest,
                                                     const SceneEntry& scene) {
  const fs::path path = sceneFile(folder, scene);
  if (!fs::exists(path)) return std::nullopt;
  const io::NpyArray array = io::readNpy(path);
  const Shape expected{manifest.frames, manifest.height, manifest.width};
  if (array.shape != expected)
    throw Error(path.string() + ": shape " + toString(array.shape) + ", expected " + toString(expected) + " (" +
                (folder / kManifest).string() + ": frames, image)");
  return array.toFloat();
}

void writeSceneSideViews(const fs::path& folder, const SideViewRolloutManifest& manifest, const SceneEntry& scene,
                         const std::vector<float>& sides) {
  io::writeNpy(sceneFile(folder, scene), io::NpyArray::fromFloats({manifest.frames, manifest.height, manifest.width}, sides));
}

std::vector<float> sideViewAt(const std::vector<float>& sides, const SideViewRolloutManifest& manifest, int k) {
  const std::size_t pixels = static_cast<std::size_t>(manifest.height) * static_cast<std::size_t>(manifest.width);
  const auto begin = sides.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(k) * pixels);
  return {begin, begin + static_cast<std::ptrdiff_t>(pixels)};
}

SynthesisedSideViews::SynthesisedSideViews(const fs::path& folder, const SceneDataset& data) : folder_(folder) {
  const fs::path path = folder / kManifest;
  if (!fs::exists(path))
    throw Error(path.string() + ": missing; make the side views with `smokesvd rollout --split training --keep-side-views " +
                folder.string() + "`");
  manifest_ = manifestFromJson(io::readJsonFile(path), path);
  const Preset& p = data.preset();
  if (manifest_.preset != p.name || manifest_.height != p.imageHeight || manifest_.width != p.imageWidth)
    throw Error(path.string() + ": side views of the " + manifest_.preset + " preset, " + std::to_string(manifest_.height) +
                " x " + std::to_string(manifest_.width) + "; expected the " + p.name + " preset's " +
                std::to_string(p.imageHeight) + " x " + std::to_string(p.imageWidth));
  const int end = manifest_.firstFrame + manifest_.frames;
  auto collect = [&](const std::vector<SceneEntry>& split, std::vector<SceneEntry>& kept) {
    for (const SceneEntry& scene : split) {
      std::optional<std::vector<float>> sides = readSceneSideViews(folder, manifest_, scene);
      if (!sides || scene.frames < end) continue;
      sides_[scene.directory.filename().string()] = std::move(*sides);
      SceneEntry cut = scene;
      cut.frames = end;
      kept.push_back(cut);
    }
  };
  collect(data.training(), training_);
  collect(data.validation(), validation_);
  if (training_.empty() && validation_.empty())
    throw Error(folder.string() + ": no side views of a scene of " + data.root().string() + " (scene_NNNN.npy)");
}

std::vector<float> SynthesisedSideViews::side(const SceneEntry& scene, int frame) const {
  const auto found = sides_.find(scene.directory.filename().string());
  if (found == sides_.end()) throw Error(folder_.string() + ": no side views of " + scene.directory.string());
  const int k = frame - manifest_.firstFrame;
  if (k < 0 || k >= manifest_.frames)
    throw Error(folder_.string() + ": frame " + std::to_string(frame) + " of " + scene.directory.filename().string() +
                " outside the rollout's frames " + std::to_string(manifest_.firstFrame) + "-" +
                std::to_string(manifest_.firstFrame + manifest_.frames - 1));
  return sideViewAt(found->second, manifest_, k);
}

std::string SynthesisedSideViews::describe() const {
  return "SvDiff's side views of " + std::to_string(training_.size()) + " training and " + std::to_string(validation_.size()) +
         " held-out scenes, frames " + std::to_string(manifest_.firstFrame) + "-" +
         std::to_string(manifest_.firstFrame + manifest_.frames - 1) + ", from " + folder_.string();
}

}  // namespace smokesvd::dataset
