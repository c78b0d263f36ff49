// Random plume scenes in the spirit of the paper's training data (100 scenes of 150 frames with random
// wind, heat and inflow): one inflow source of random shape, size and position near the floor, with
// noise; random density buoyancy and, for some scenes, heat; a slowly turning horizontal wind; some
// vorticity confinement; sometimes an obstacle in the plume's way; walls with an open top. Lengths and
// accelerations scale with the grid so a scene looks alike at every resolution. The draw uses only
// std::mt19937_64 (whose output the C++ standard fixes), so a seed gives the same scene everywhere;
// scene.json records every drawn value anyway.
#pragma once

#include <array>
#include <cstdint>

#include "pipeline/sim/scene.h"

namespace smokesvd::sim {

Scene randomScene(uint64_t seed, const std::array<int64_t, 3>& resolution, int frames);

}  // namespace smokesvd::sim
