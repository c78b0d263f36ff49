// The cell flags of a scene at one frame: the outer layer of cells is wall (obstacle) or open (empty)
// per side, cells whose centre lies inside an active obstacle are obstacles, the rest fluid. Where an
// open side meets a wall side the wall wins.
#pragma once

#include <vector>

#include "pipeline/physics/grid.h"
#include "pipeline/sim/scene.h"

namespace smokesvd::sim {

// Signed distance in cells from p to the shape (negative inside).
double signedDistance(const Geometry& shape, const Vec3& p);

// Flags [z, y, x] as floats (1 fluid, 2 obstacle, 4 empty) for the obstacles active at `frame`.
std::vector<float> sceneFlags(const Scene& scene, int frame);

// True when some obstacle appears or disappears at `frame` (the flags differ from frame − 1's).
bool obstaclesChangeAt(const Scene& scene, int frame);

}  // namespace smokesvd::sim
