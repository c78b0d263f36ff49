// Differentiable advection A(field, u, inflow, dt) = advect(field by u over dt) + inflow, as
// mantaflow's advectSemiLagrange computes it (docs/physics.md states every rule):
//   - a scalar field [D, H, W] at cell centres is traced by the centred velocity; a MAC field
//     [3, D, H, W] (e.g. the velocity itself, self-advection) component by component, each traced by
//     the velocity at its faces;
//   - semi-Lagrangian: trilinear lookups clamped to the cell centres 0.5 … n − 0.5;
//   - MacCormack: strength 1 by default, mantaflow's revert-to-first-order clamp (clampMode 2);
//   - the outer cell layer of A(field) is 0; the inflow is added everywhere after advection.
// The velocity u is a MAC grid [3, D, H, W] in cells per step; the FlagGrid (grid.h) holds the cells'
// flags (mantaflow's bits) and the masks derived from them.
#pragma once

#include "pipeline/physics/grid.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

enum class AdvectionScheme { SemiLagrangian = 1, MacCormack = 2 };

struct AdvectionParams {
  AdvectionScheme scheme = AdvectionScheme::MacCormack;
  float dt = 1.0f;        // time step; velocity is in cells per unit of time
  float strength = 1.0f;  // MacCormack correction strength
};

// What a MacCormack forward leaves for its backward: the first-order (semi-Lagrangian) pass like
// the field, and per cell and plane the trace (v, field) and the clamp's range (low, high, first
// order, 0) as vec4s, [planes, D, H, W, 4]. Empty for the semi-Lagrangian scheme.
struct AdvectionCache {
  Tensor firstOrder;
  Tensor trace;
  Tensor bounds;
};

// out = A(field) + inflow. `inflow` (like field) may be null. `cache`, if given, receives what
// advectBackward can reuse. `out` must not alias an input.
void advect(Stream& stream, const FlagGrid& grid, const Tensor& field, const Tensor& velocity, const Tensor* inflow,
            const AdvectionParams& params, const Tensor& out, AdvectionCache* cache = nullptr);

// Where advectBackward writes; a null pointer means that gradient is not wanted. ∂L/∂inflow is the
// upstream gradient itself, so it needs no kernel.
struct AdvectionGradients {
  const Tensor* field = nullptr;     // like field
  const Tensor* velocity = nullptr;  // [3, D, H, W], MAC
};

// Vector-Jacobian products of A at (field, velocity) for the upstream gradient gradOut (like field),
// with the clamp's keep/revert decisions and the stencil cells held fixed. `cache` is what advect left
// for the same inputs, or null to recompute it.
void advectBackward(Stream& stream, const FlagGrid& grid, const Tensor& field, const Tensor& velocity,
                    const AdvectionParams& params, const Tensor& gradOut, const AdvectionCache* cache,
                    const AdvectionGradients& gradients);

}  // namespace smokesvd::physics
