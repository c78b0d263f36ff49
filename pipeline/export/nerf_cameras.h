// The orthographic orbit views of a run as pinhole cameras in the NeRF convention (transform_matrix
// camera-to-world, OpenGL axes: the camera looks down its -z, +y up, +x right; world as in world_placement.h).
//
// NeRF and 3D Gaussian Splatting tools take pinhole cameras only (nerfstudio's OPENCV model, the NeRF-synthetic
// camera_angle_x), so each orthographic view becomes a pinhole camera on its central ray at distance D behind
// the plane through the box centre, with focal lengths fx = D / (world width of a pixel), fy likewise: points on
// that plane project exactly where the orthographic view puts them, a point at depth offset d and s pixels from
// the image centre lands s |d| / (D + d) pixels off. D is the smallest distance (the same for every view) that
// keeps this error at or below `maxErrorPixels` over a 9 x 9 x 9 lattice of the box, its corners and edges
// included; the error actually reached is reported. A farther camera is more exact and makes the scene a
// smaller part of the cameras' extent, which some tools scale their step sizes by (docs/applications.md).
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>

#include "pipeline/camera/camera.h"
#include "pipeline/export/world_placement.h"

namespace smokesvd::exporters {

struct PinholeCamera {
  glm::dmat4 cameraToWorld{1.0};
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels; cx = w / 2, cy = h / 2 (pixel centres at c + 1/2)
  int width = 0, height = 0;
};

struct PinholeApproximation {
  std::vector<PinholeCamera> cameras;
  double distance = 0;           // D, world units
  double maxErrorPixels = 0;     // over the lattice, all views
  bool squarePixels = true;      // fx == fy (what camera_angle_x alone can express)
};

// Error if a view has no pinhole equivalent (its image axes are not orthogonal in the world: voxels that are
// not square in the horizontal plane).
PinholeApproximation pinholeCameras(const std::vector<Camera>& views, const GridSize& grid,
                                    const WorldPlacement& placement, double maxErrorPixels);

// Pixel coordinates (u, v) of a world point through a pinhole camera (u right, v down, as the renderer's).
glm::dvec2 projectPinhole(const PinholeCamera& camera, const glm::dvec3& world);

}  // namespace smokesvd::exporters
