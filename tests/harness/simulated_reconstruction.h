// A folder shaped like a finished `smokesvd reconstruct` run, made in seconds from a simulation instead of
// networks: a rising plume (density buoyancy, a source that pushes upward, no obstacles, walls with an open
// top) simulated on `grid` for a warm-up and then `frames` frames, those frames renumbered from 0 under the
// reconstruction's names (frame 0's inflow is its whole density, as in a reconstruction), a box scene.json,
// 16 orbit renders per frame and a run.json that says "command": "smokesvd reconstruct". Its velocities are
// divergence-free and its fields obey density[t] = A(density[t-1], velocity[t-1]) + inflow[t] exactly for
// t >= 1, as a reconstruction's do.
#pragma once

#include <filesystem>
#include <string>

#include "nets/io/temporary_folder.h"
#include "runtime/context.h"
#include "runtime/geometry.h"

namespace smokesvd::testing {

void writeSimulatedReconstruction(Context& context, const std::filesystem::path& folder, int frames,
                                  const GridSize& grid = {.x = 16, .y = 28, .z = 16});

// The scratch folder of a test program that reads one such reconstruction: an io::TemporaryFolder named after
// `purpose`, with the reconstruction of `frames` frames in its "recon" subfolder, written (on the shared
// test context) the first time reconstruction() is asked for.
class SimulatedReconstructionScratch {
 public:
  SimulatedReconstructionScratch(const std::string& purpose, int frames);
  const io::TemporaryFolder& root() const { return root_; }
  const std::filesystem::path& reconstruction();

 private:
  io::TemporaryFolder root_;
  int frames_;
  bool written_ = false;
  std::filesystem::path reconstruction_;
};

}  // namespace smokesvd::testing
