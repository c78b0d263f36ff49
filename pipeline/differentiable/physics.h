// Differentiable physics ops on the autograd tape (wrappers of pipeline/physics/), each also
// registered for `smokesvd op`. Velocities are planar [3, D, H, W] (docs/conventions.md).
#pragma once

#include "nets/autograd/tape.h"
#include "pipeline/physics/advection.h"
#include "pipeline/physics/differential.h"
#include "pipeline/physics/grid.h"

namespace smokesvd::diff {

// A(field, velocity) + inflow (pipeline/physics/advection.h). `inflow` may be null. The field may be
// the velocity itself (MAC self-advection); its gradient then sums both roles.
Var advect(Tape& tape, const physics::FlagGrid& grid, const Var& field, const Var& velocity, const Var& inflow,
           const physics::AdvectionParams& params);

Var macToCentred(Tape& tape, const Var& mac);
Var centredToMac(Tape& tape, const Var& centred);
Var divergence(Tape& tape, const Var& velocity, physics::Staggering staggering);
Var curl(Tape& tape, const Var& velocity);
Var gradientNormSquared(Tape& tape, const Var& velocity);

// [D, H, W, 3] <-> [3, D, H, W].
Var velocityToPlanar(Tape& tape, const Var& interleaved);
Var velocityToInterleaved(Tape& tape, const Var& planar);

}  // namespace smokesvd::diff
