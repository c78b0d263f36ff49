// Simulated scenes as training data: a folder written by `smokesvd simulate --scenes N --out DIR`
// (DIR/scene_NNNN/{scene.json, flags.npz, fields/...}), split by scene into training and validation.
//
// Everything is returned in the networks' units (docs/models.md):
//   - densities and inflows in reference-absorption units, rho * absorption_scene / absorption_preset, so
//     that the preset's reference absorption renders them exactly as the scene's own absorption rendered
//     the simulated density (how thick smoke looks is then a property of the density, not of the camera);
//   - the look of a scene with its brightness normalised, ambient + light intensity = 1 (how bright the
//     footage is says nothing about the smoke; reconstruction normalises its input the same way);
//   - velocities as planar MAC fields [3, D, H, W] in cells per step, as the simulator writes them.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/preset.h"
#include "pipeline/render/renderer.h"
#include "pipeline/sim/scene.h"

namespace smokesvd::dataset {

struct SceneEntry {
  std::filesystem::path directory;
  sim::Scene scene;
  int index = 0;   // position among all scenes of the folder (sorted by name)
  int frames = 0;  // consecutive frames 0 .. frames-1 with their fields on disk
};

struct DatasetOptions {
  int validationEvery = 10;  // scenes index % validationEvery == validationEvery - 1 are held out
  int minFrames = 1;         // scenes with fewer frames on disk are skipped
};

class SceneDataset {
 public:
  // Finds every scene_*/ folder of `root`. Errors: no scene at all, a scene of another resolution than
  // the preset, or no scene left for training or validation; each names the folder and what was expected.
  SceneDataset(const std::filesystem::path& root, const Preset& preset, DatasetOptions options = {});

  const std::filesystem::path& root() const { return root_; }
  const Preset& preset() const { return preset_; }
  const std::vector<SceneEntry>& training() const { return training_; }
  const std::vector<SceneEntry>& validation() const { return validation_; }

  std::vector<float> density(const SceneEntry& scene, int frame) const;   // [D, H, W], reference units
  std::vector<float> inflow(const SceneEntry& scene, int frame) const;    // [D, H, W], reference units
  std::vector<float> velocity(const SceneEntry& scene, int frame) const;  // [3, D, H, W], MAC, planar
  std::vector<float> flags(const SceneEntry& scene) const;                // [D, H, W], mantaflow bits
  // The scene's look in the networks' units: the preset's absorption (light absorption scaled alike),
  // ambient and light intensity divided by their sum; step 1; a light only if the scene has one.
  render::RenderSettings look(const SceneEntry& scene) const;
  // rho_reference / rho_scene for this scene.
  float densityScale(const SceneEntry& scene) const;

 private:
  std::filesystem::path root_;
  Preset preset_;
  std::vector<SceneEntry> training_, validation_;
};

}  // namespace smokesvd::dataset
