#version 450
#extension GL_GOOGLE_include_directive : require
// Squared Frobenius norm of the velocity gradient per cell, for a cell-centred velocity [3, D, H, W]:
//   out(c) = Σ_k Σ_d (∂_d u_k(c))²   (gradient_stencil.glsl has ∂ and the index names).
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Norm { float norm[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    for (int d = 0; d < 3; ++d) {
      const float partial = difference(velocity, k, c, d);
      sum += partial * partial;
    }
  }
  norm[cellIndex(c)] = sum;
}
