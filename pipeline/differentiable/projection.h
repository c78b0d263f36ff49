// Pressure projection on the autograd tape, and as the `smokesvd op project` op.
//
//   y = P u = u − ∇p,   A p = −div(u)   (pipeline/physics/pressure.h)
//
// P is linear and, with exact solves, symmetric (the discrete gradient is minus the transpose of the
// divergence on the fluid's faces, and faces touching obstacles are zeroed on both sides), so its
// adjoint is itself: grad_u = P grad_y, one more solve with the same flags. Both solves stop at the
// solver's relative residual, which bounds how far the computed adjoint is from the exact one.
#pragma once

#include <memory>

#include "nets/autograd/tape.h"
#include "pipeline/physics/pressure.h"

namespace smokesvd::diff {

// The solver runs its own submits: the tape's stream is submitted (and restarted) before each solve, so
// a projection splits a recording in two. Throws Error if a solve does not reach its tolerance.
Var project(Tape& tape, const std::shared_ptr<physics::PressureSolver>& solver, const Var& velocity);

}  // namespace smokesvd::diff
