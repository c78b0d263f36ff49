// SvDiff's side views of simulated scenes, kept on disk: what `smokesvd rollout --keep-side-views DIR` writes and
// the NvRef trainer reads (options.side_views) to train on the side views inference gives it.
//
// DIR/rollout.json   {"preset", "first_frame", "frames", "image": [h, w], "history", "sampling": {...}}: how they were made
// DIR/scene_NNNN.npy [frames, h, w] float32: the side views of scene frames first_frame .. first_frame + frames - 1,
//                    in the networks' units (scene_dataset.h), one file per scene, written when its rollout ends
//
// A rollout into a folder that already holds a rollout.json must describe the same rollout (else an Error
// names the field that differs), and reuses the scenes already there: a rollout of many scenes resumes.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/dataset/scene_dataset.h"

namespace smokesvd::dataset {

struct SideViewRolloutManifest {
  std::string preset;
  int firstFrame = 0, frames = 0, height = 0, width = 0;
  nlohmann::json how;  // "history" and "sampling": recorded and compared, not interpreted

  nlohmann::json toJson() const;
};

// Writes DIR/rollout.json, or checks that the one there matches (Error naming the file and the field).
void prepareSideViewFolder(const std::filesystem::path& folder, const SideViewRolloutManifest& manifest);

// The side views kept for `scene` ([frames * h * w]), or nothing when the folder has none for it; an Error
// if its file is not of the manifest's shape.
std::optional<std::vector<float>> readSceneSideViews(const std::filesystem::path& folder, const SideViewRolloutManifest& manifest,
                                                     const SceneEntry& scene);
void writeSceneSideViews(const std::filesystem::path& folder, const SideViewRolloutManifest& manifest, const SceneEntry& scene,
                         const std::vector<float>& sides);
// Frame k (0 .. frames-1) of a scene's side views as read or written above: [h * w].
std::vector<float> sideViewAt(const std::vector<float>& sides, const SideViewRolloutManifest& manifest, int k);

// A folder's side views for the scenes of `data` it holds, for training.
class SynthesisedSideViews {
 public:
  // Errors: no rollout.json, another preset's or image size, no scene of `data` in the folder.
  SynthesisedSideViews(const std::filesystem::path& folder, const SceneDataset& data);

  const SideViewRolloutManifest& manifest() const { return manifest_; }
  // The scenes of a split that have side views, their `frames` cut to the last frame kept (so that
  // frames drawn from them have side views) and all earlier frames of the scene on disk.
  const std::vector<SceneEntry>& training() const { return training_; }
  const std::vector<SceneEntry>& validation() const { return validation_; }
  // The side view [h * w] of a scene frame (first_frame <= frame < first_frame + frames).
  std::vector<float> side(const SceneEntry& scene, int frame) const;
  std::string describe() const;  // "side views of N training and M held-out scenes, frames A-B, from DIR"

 private:
  std::filesystem::path folder_;
  SideViewRolloutManifest manifest_;
  std::map<std::string, std::vector<float>> sides_;  // by scene folder name
  std::vector<SceneEntry> training_, validation_;
};

}  // namespace smokesvd::dataset
