// What a simulation run writes into its output directory (docs/simulation.md has the full layout):
//   scene.json                         every parameter, enough to reproduce the run
//   flags.npz                          "flags" [z, y, x] int32 at frame 0 (1 fluid, 2 obstacle, 4 empty)
//   fields/density_NNNN.npz            "density" [z, y, x]
//   fields/velocity_NNNN.npz           "velocity" [z, y, x, 3], MAC (mantaflow's layout)
//   fields/inflow_NNNN.npz             "inflow" [z, y, x], the density the sources added in frame NNNN
//   fields/temperature_NNNN.npz        "temperature" [z, y, x], when the scene tracks temperature
//   renders/view_VV/NNNN.png           the density rendered from orbit view VV (16-bit gray)
//   checkpoint.npz                     the state after the last frame written (to resume or extend the run)
//   run.json                           status: {"complete": ..., "frames": N}
//   manifest.txt                       every file above, listed before it is written (run_files.h)
// Every file is written under a temporary name and renamed, so an interrupted run never leaves a
// truncated file under a final name.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/sim/run_files.h"
#include "pipeline/sim/simulator.h"

namespace smokesvd::sim {

std::string frameName(int frame);  // "0042"

// Writes the fields of the simulator's last completed frame (frame() − 1). Throws Error, writing nothing,
// if a field holds NaN or infinity (naming the frame, the field and the first bad cell).
void writeFrameFields(RunFiles& files, const Simulator& simulator);
// Writes the density, velocity and inflow files of `frame` from host values: density and inflow [D, H, W],
// velocity planar MAC [3, D, H, W].
void writeFields(const std::filesystem::path& directory, int frame, const GridSize& grid, const std::vector<float>& density,
                 const std::vector<float>& velocity, const std::vector<float>& inflow);
void writeFlags(RunFiles& files, const Simulator& simulator);

// Checkpoint of the simulator after its last completed frame.
void writeCheckpoint(RunFiles& files, const Simulator& simulator);
// The saved state, or nothing if the directory holds no checkpoint. A checkpoint that cannot be read is an
// Error that says what to do (delete it, or --overwrite).
std::optional<SimulatorState> readCheckpoint(const std::filesystem::path& directory, const Scene& scene);

}  // namespace smokesvd::sim
