#include "pipeline/reconstruct/inflow_mask.h"

#include <cmath>

namespace smokesvd::reconstruct {

std::vector<float> inflowMask(const GridSize& g, double heightFraction) {
  std::vector<float> mask(static_cast<std::size_t>(g.cells()), 0.0f);
  const auto top = static_cast<int64_t>(std::ceil(heightFraction * static_cast<double>(g.y)));
  for (int64_t z = 1; z + 1 < g.z; ++z)
    for (int64_t y = 1; y + 1 < g.y && y < top; ++y)
      for (int64_t x = 1; x + 1 < g.x; ++x) mask[static_cast<std::size_t>((z * g.y + y) * g.x + x)] = 1.0f;
  return mask;
}

}  // namespace smokesvd::reconstruct
