// Differentiable advection A(field, u, inflow, dt) = advect(field by u over dt) + inflow, as
// mantaflow's advectSemiLagrange computes it (docs/physics.md states every rule):
//   - a scalar field [D, H, W] at cell centres is traced by the centred velocity; a MAC field
//     [3, D, H, W] (e.g. the velocity itself, self-advection) component by component, each traced by
//     the velocity at its faces;
//   - semi-Lagrangian: trilinear lookups clamped to the cell centres 0.5 … n − 0.5;
//   - MacCormack: strength 1 by default, mantaflow's revert-to-first-order clamp (clampMode 2);
//   - the outer cell layer of A(field) is 0; the inflow is added everywhere after advection.
// The velocity u is a MAC grid [3, D, H, W] in cells per step; flags [D, H, W] hold mantaflow's bits.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

enum class AdvectionScheme { SemiLagrangian = 1, MacCormack = 2 };

struct AdvectionParams {
  AdvectionScheme scheme = AdvectionScheme::MacCormack;
  float dt = 1.0f;        // time step; velocity is in cells per unit of time
  float strength = 1.0f;  // MacCormack correction strength
};

// AdvectionScheme from "sl" / "semi-lagrangian" / "mc" / "maccormack"; Error otherwise.
AdvectionScheme parseAdvectionScheme(const std::string& name);

// out = A(field) + inflow. `inflow` (like field) may be null. For MacCormack, `firstOrder` (like
// field) may receive the semi-Lagrangian pass for advectBackward; otherwise a temporary holds it.
// `out` must not alias an input.
void advect(Stream& stream, const Tensor& flags, const Tensor& field, const Tensor& velocity, const Tensor* inflow,
            const AdvectionParams& params, const Tensor& out, const Tensor* firstOrder = nullptr);

// Where advectBackward writes; a null pointer means that gradient is not wanted. ∂L/∂inflow is the
// upstream gradient itself, so it needs no kernel.
struct AdvectionGradients {
  const Tensor* field = nullptr;     // like field
  const Tensor* velocity = nullptr;  // [3, D, H, W], MAC
};

// Vector-Jacobian products of A at (field, velocity) for the upstream gradient gradOut (like field),
// with the clamp's keep/revert decisions and the stencil cells held fixed. `firstOrder` is what advect
// wrote there (MacCormack), or null to recompute it.
void advectBackward(Stream& stream, const Tensor& flags, const Tensor& field, const Tensor& velocity,
                    const AdvectionParams& params, const Tensor& gradOut, const Tensor* firstOrder,
                    const AdvectionGradients& gradients);

}  // namespace smokesvd::physics
