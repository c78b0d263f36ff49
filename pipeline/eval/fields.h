// The volumes evaluation compares, read from the two folder layouts that hold them (docs/evaluation.md):
//   a finished `smokesvd reconstruct` run (pipeline/reconstruct/reconstruction.h lists its files): run.json's
//   box, frames, input framing, region and intensity mapping, and its fields in the networks' units;
//   a `smokesvd simulate` scene (docs/simulation.md): its fields in simulation units, returned in the
//   networks' units of a given absorption, rho * absorption_scene / absorption (pipeline/dataset/scene_dataset.h).
// Densities come back [D, H, W], velocities planar MAC [3, D, H, W] in cells per step. Errors name the folder or
// file and what was expected.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/reconstruct/front_views.h"
#include "pipeline/render/renderer.h"
#include "pipeline/sim/scene.h"

namespace smokesvd::eval {

struct ReconstructionRun {
  std::filesystem::path folder;
  std::string preset;
  GridSize grid;
  float absorption = 0;      // the box's reference absorption: render with it, ambient 1, no light
  int frames = 0;            // reconstructed frames
  int firstFrame = 0;        // the input frame of reconstruction frame 0
  reconstruct::Framing framing = reconstruct::Framing::Box;
  std::filesystem::path input, calibration;
  std::string camera;        // the calibrated view of the input (its file name)
  int sourceWidth = 0, sourceHeight = 0;
  reconstruct::Region region;
  reconstruct::IntensityMapping mapping;
  nlohmann::json models;     // the networks' hashes, as run.json records them

  render::RenderSettings look() const;
  std::vector<float> density(int frame) const;
  std::vector<float> velocity(int frame) const;
};

// Error unless `folder` holds a complete reconstruction.
ReconstructionRun readReconstructionRun(const std::filesystem::path& folder);

struct TruthScene {
  std::filesystem::path folder;
  sim::Scene scene;
  int frames = 0;  // consecutive frames 0 .. frames-1 with density and velocity on disk

  std::vector<float> density(int frame, float absorption) const;  // in the networks' units of `absorption`
  std::vector<float> velocity(int frame) const;
};

// Error unless `folder` holds scene.json and the fields of frame 0.
TruthScene readTruthScene(const std::filesystem::path& folder);

// [z, y, x, 3] interleaved, as files hold velocities, to planar [3, z, y, x].
std::vector<float> planarVelocity(const std::vector<float>& interleaved);

}  // namespace smokesvd::eval
