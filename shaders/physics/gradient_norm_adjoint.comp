#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of gradient_norm.comp: from g = ∂L/∂out [D, H, W] to ∂L/∂u [3, D, H, W],
//   gradVelocity_k(j) = Σ_d Σ_{i = j + s·e_d, s ∈ {−1, 0, 1}} weight(i_d, j_d)·2·g(i)·∂_d u_k(i)
// (∂_dᵀ applied to 2·g·∂_d u_k; gradient_stencil.glsl has ∂, weight and the index names).
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(binding = 1) uniform samplerBuffer gradNorm;
layout(std430, binding = 2) writeonly buffer GradVelocity { float gradVelocity[]; };

void main() {
  const ivec3 j = ivec3(gl_GlobalInvocationID);
  if (!inGrid(j)) return;
  for (int k = 0; k < 3; ++k) {
    float sum = 0.0;
    for (int d = 0; d < 3; ++d) {
      for (int s = -1; s <= 1; ++s) {
        const ivec3 i = j + s * unitStep(d);
        if (!inGrid(i)) continue;
        const float weight = differenceWeight(i[d], j[d], n[d]);
        if (weight != 0.0) sum += weight * 2.0 * valueAt(gradNorm, 0, i) * difference(velocity, k, i, d);
      }
    }
    gradVelocity[k * cellCount() + cellIndex(j)] = sum;
  }
}
