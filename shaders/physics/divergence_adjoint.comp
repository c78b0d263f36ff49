#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of divergence.comp: from g = ∂L/∂div [D, H, W] to ∂L/∂u [3, D, H, W], per cell c and component d:
//   STAGGERED = 1 (MAC):     gradVelocity_d(c) = g(c − e_d) − g(c)   (g before cell 0 = 0)
//   STAGGERED = 0 (centred): gradVelocity_d(c) = (∂_dᵀ g)(c)
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int STAGGERED = 1;

layout(binding = 0) uniform samplerBuffer gradDivergence;
layout(std430, binding = 1) writeonly buffer GradVelocity { float gradVelocity[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  for (int d = 0; d < 3; ++d) {
    float value;
    if (STAGGERED != 0) {
      const ivec3 down = c - unitStep(d);
      value = (inGrid(down) ? valueAt(gradDivergence, 0, down) : 0.0) - valueAt(gradDivergence, 0, c);
    } else {
      value = differenceTransposed(gradDivergence, 0, c, d);
    }
    gradVelocity[d * cellCount() + cellIndex(c)] = value;
  }
}
