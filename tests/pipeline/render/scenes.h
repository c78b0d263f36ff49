// Small scenes shared by the render tests: odd-sized grids, orbit cameras and a perspective camera.
#pragma once

#include <vector>

#include "pipeline/camera/calibration.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::testing {

// A perspective camera of `width` x `height` pixels looking at the grid's centre from `eye` (grid units),
// built through the calibrated-camera path (NeRF JSON conventions).
Camera lookAtCamera(const GridSize& grid, const Vec3& eye, int width, int height, double fieldOfViewX = 1.0);

// Orbit cameras at 0, 37 and 90 degrees plus one perspective camera, all width x height.
std::vector<Camera> mixedCameras(const GridSize& grid, int width, int height);

render::RenderSettings unlitSettings();
render::RenderSettings litSettings();

}  // namespace smokesvd::testing
