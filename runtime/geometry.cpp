#include "runtime/geometry.h"

#include "runtime/error.h"

namespace smokesvd {

void checkGridSize(const GridSize& grid, const std::string& what) {
  const std::string sizes = std::to_string(grid.x) + " x " + std::to_string(grid.y) + " x " + std::to_string(grid.z);
  for (int64_t side : {grid.x, grid.y, grid.z})
    if (side < 1 || side > kMaxGridSide)
      throw Error(what + ": grid " + sizes + " (x, y, z): every side must be from 1 to " + std::to_string(kMaxGridSide) +
                  " cells");
  if (grid.cells() > kMaxGridCells)
    throw Error(what + ": grid " + sizes + " (x, y, z) has " + std::to_string(grid.cells()) + " cells, more than the " +
                std::to_string(kMaxGridCells) + " smokesvd accepts");
}

}  // namespace smokesvd
