// Where a reconstruction's inflow may be: 1 in the cells below `heightFraction` of the box and off its
// outer cell layer, 0 elsewhere ([D, H, W]).
#pragma once

#include <vector>

#include "runtime/geometry.h"

namespace smokesvd::reconstruct {

std::vector<float> inflowMask(const GridSize& grid, double heightFraction);

}  // namespace smokesvd::reconstruct
