#include "pipeline/export/mantaflow_files.h"

#include "nets/io/npy.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/outputs.h"

namespace smokesvd::exporters {
namespace fs = std::filesystem;

nlohmann::json writeMantaflow(const sim::SavedRun& run, const fs::path& out) {
  const GridSize g = run.grid();
  const Shape scalar{g.z, g.y, g.x, 1}, vector{g.z, g.y, g.x, 3};
  for (int t = 0; t < run.frames; ++t) {
    const std::string name = sim::frameName(t);
    io::writeNpz(out / ("density_" + name + ".npz"), {{"arr_0", io::NpyArray::fromFloats(scalar, run.density(t))}});
    io::writeNpz(out / ("inflow_" + name + ".npz"), {{"arr_0", io::NpyArray::fromFloats(scalar, run.inflow(t))}});
    io::writeNpz(out / ("velocity_" + name + ".npz"),
                 {{"arr_0", io::NpyArray::fromFloats(vector, io::readNpzMember(run.field("velocity", t), "velocity").toFloat())}});
  }
  const std::vector<float> flags = sim::sceneFlags(run.scene, 0);
  io::writeNpz(out / "flags.npz", {{"arr_0", io::NpyArray::fromInts(scalar, std::vector<int32_t>(flags.begin(), flags.end()))}});
  return {{"files",
           {{"density_NNNN.npz", "arr_0 float32 [z, y, x, 1], RealGrid"},
            {"velocity_NNNN.npz", "arr_0 float32 [z, y, x, 3], MACGrid: [..., 0] u_x at the lower x-face (i, j+1/2, k+1/2), "
                                  "[..., 1] u_y at (i+1/2, j, k+1/2), [..., 2] u_z at (i+1/2, j+1/2, k)"},
            {"inflow_NNNN.npz", "arr_0 float32 [z, y, x, 1], RealGrid: the density added in frame NNNN"},
            {"flags.npz", "arr_0 int32 [z, y, x, 1], FlagGrid: 1 fluid, 2 obstacle, 4 empty (frame 0)"}}},
          {"grid_size", {g.x, g.y, g.z}},
          {"units", "cells per step, one step per frame: set the solver's timestep to 1"},
          {"relation", "density[t] = advectSemiLagrange(density[t-1], velocity[t-1], order=2) + inflow[t]"}};
}

}  // namespace smokesvd::exporters
