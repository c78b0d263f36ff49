#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of curl.comp: from g = ∂L/∂ω [3, D, H, W] to ∂L/∂u, with ω_d = ∂_a u_b − ∂_b u_a for
// (d, a, b) cyclic:   gradVelocity_b += ∂_aᵀ g_d,   gradVelocity_a −= ∂_bᵀ g_d, i.e. per component k
//   gradVelocity_k(c) = (∂_{k+2}ᵀ g_{k+1})(c) − (∂_{k+1}ᵀ g_{k+2})(c)   (indices mod 3).
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer gradCurl;
layout(std430, binding = 1) writeonly buffer GradVelocity { float gradVelocity[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  for (int k = 0; k < 3; ++k) {
    const int next = (k + 1) % 3, last = (k + 2) % 3;
    gradVelocity[k * cellCount() + cellIndex(c)] =
        differenceTransposed(gradCurl, next, c, last) - differenceTransposed(gradCurl, last, c, next);
  }
}
