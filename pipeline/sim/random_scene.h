// Random smoke scenes in the spirit of the paper's training data (100 scenes of 150 frames with random
// wind, heat and inflow), widened to what people film: a rising plume, a puff whose inflow stops, a
// sideways jet, or two sources the second of which starts later; sources of random shape, size and
// height with noise; random density buoyancy and, for some scenes, heat; a horizontal wind that turns;
// some vorticity confinement; sometimes an obstacle; walls with an open top; and a per-scene look
// (absorption, even ambient light or a directional light). docs/simulation.md lists the distribution.
// Lengths and accelerations scale with the grid so a scene looks alike at every resolution. The draw
// uses only std::mt19937_64 (whose output the C++ standard fixes), so a seed gives the same scene
// everywhere; scene.json records every drawn value anyway.
#pragma once

#include <array>
#include <cstdint>

#include "pipeline/sim/scene.h"

namespace smokesvd::sim {

Scene randomScene(uint64_t seed, const GridSize& resolution, int frames);

}  // namespace smokesvd::sim
