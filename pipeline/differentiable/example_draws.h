// Input draws (nets/op_example.h) for the examples of the physics ops: mantaflow flag grids.
#pragma once

#include "nets/op_example.h"

namespace smokesvd::diff {

// Flags [D, H, W] of a closed box (a one-cell obstacle wall) whose interior cells are, at random,
// obstacles with probability `obstacles`, empty with probability `empty`, else fluid. Not differentiated.
InputDraw flagsDraw(Shape shape, float obstacles = 0.08f, float empty = 0.08f);

}  // namespace smokesvd::diff
