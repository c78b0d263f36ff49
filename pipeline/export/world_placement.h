// Where an exported run's box lies in the world, and in which units. Every exporter uses it, so a VDB volume,
// the NeRF cameras and a mantaflow grid of one run agree:
//   calibrated footage (the run records its NeRF-style calibration, or --calibration gives one): the
//     calibration's world, in its units (metres for ScalarFlow): grid -> world = VolumeBox::gridToWorld
//     (pipeline/camera/calibration.h);
//   otherwise: the box is 1 world unit wide along x, its voxels cubes of 1/W, centred at the origin, y up
//     (the scale at which NeRF and 3D Gaussian Splatting tools expect a scene).
// `zUp` turns the y-up world into a z-up one (Blender): (x, y, z) -> (x, -z, y).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "pipeline/sim/saved_run.h"

namespace smokesvd::exporters {

struct WorldPlacement {
  glm::dmat4 gridToWorld{1.0};   // grid coordinates (cells, docs/conventions.md) -> world
  std::string origin;            // "calibration FILE" or "unit box"
  bool zUp = false;

  glm::dmat3 linear() const { return glm::dmat3(gridToWorld); }
  nlohmann::json describe() const;
};

// Error naming the file if a recorded or given calibration cannot be read.
WorldPlacement placementOf(const sim::SavedRun& run, const std::optional<std::filesystem::path>& calibration, bool zUp);

}  // namespace smokesvd::exporters
