// External forces on the MAC velocity [3, D, H, W] (cells per step): buoyancy from density and
// temperature, uniform accelerations (wind, gravity), cell-centred force fields and vorticity
// confinement. Each acts on the faces mantaflow's KnApplyForceField does: neither neighbouring cell
// an obstacle, at least one fluid; the other faces are copied. Every function writes `out`, which must
// not alias `velocity`. docs/simulation.md states the formulas. Grids whose width is a multiple of 4 run
// block variants of the kernels (four cells per invocation, vec4 texels), others one cell per invocation.
#pragma once

#include <array>
#include <glm/vec3.hpp>

#include "pipeline/physics/grid.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

// u_a += dt·(uniform_a + perDensity_a·ρ̄ + perTemperature_a·T̄), ρ̄ and T̄ averaged over the face's two cells.
// mantaflow's addBuoyancy(density, gravity, coefficient) is perDensity = −coefficient·gravity.
// Float, as the kernels take them (smokesvd::Vec3, double, converts with glm::vec3(v)).
struct Buoyancy {
  glm::vec3 uniform{0, 0, 0};         // wind or any uniform acceleration
  glm::vec3 perDensity{0, 0, 0};      // acceleration per unit density
  glm::vec3 perTemperature{0, 0, 0};  // acceleration per unit temperature (ignored without a temperature field)
};

// `temperature` may be null.
void addBuoyancy(Stream& stream, const Tensor& flags, const Tensor& density, const Tensor* temperature,
                 const Tensor& velocity, const Buoyancy& buoyancy, float dt, const Tensor& out);

// u_a += dt·½(f_a(c) + f_a(c − e_a)) for a cell-centred acceleration field f [3, D, H, W].
void addForceField(Stream& stream, const Tensor& flags, const Tensor& force, const Tensor& velocity, float dt,
                   const Tensor& out);

// ω and |ω| at cell centres, [4, D, H, W] (centred velocity, central differences; 0 on the outer layer).
void vorticityField(Stream& stream, const Tensor& velocity, const Tensor& vorticity);

// The confinement force ε·N×ω at cell centres, [3, D, H, W] (0 on the outer layer).
void vorticityForce(Stream& stream, const Tensor& vorticity, float strength, const Tensor& force);

// Vorticity confinement with strength ε from a vorticity field of vorticityField(): vorticityForce
// applied like a force field.
void addVorticityConfinement(Stream& stream, const Tensor& flags, const Tensor& vorticity, const Tensor& velocity,
                             float strength, float dt, const Tensor& out);

}  // namespace smokesvd::physics
