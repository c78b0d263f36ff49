// A run in mantaflow's own .npz layout, so that it continues in mantaflow (tum-pbs/mantaflow, whose
// fileio/iogrids.cpp writeGridNumpy/readGridNumpy define it): one array "arr_0" per file, float32 (the
// flags int32), shape [z, y, x, 1] for scalar grids and [z, y, x, 3] for vector and MAC grids; Grid::load
// checks the sizes and the last dimension. Per frame OUT/density_NNNN.npz (RealGrid), velocity_NNNN.npz
// (MACGrid: component x at the lower x-face, as docs/conventions.md and ../shared/testdata/mantaflow state),
// inflow_NNNN.npz (RealGrid), and OUT/flags.npz (FlagGrid: 1 fluid, 2 obstacle, 4 empty) of frame 0.
// Velocities stay in cells per step with one step a frame: set the solver's timestep to 1.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "pipeline/sim/saved_run.h"

namespace smokesvd::exporters {

nlohmann::json writeMantaflow(const sim::SavedRun& run, const std::filesystem::path& out);

}  // namespace smokesvd::exporters
