#version 450
#extension GL_GOOGLE_include_directive : require
// Divergence of a velocity [3, D, H, W] per cell c (gradient_stencil.glsl has ∂ and the index names):
//   STAGGERED = 1 (MAC):     div(c) = Σ_d u_d(c + e_d) − u_d(c)   (u_d past the last cell = 0)
//   STAGGERED = 0 (centred): div(c) = Σ_d ∂_d u_d(c)
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int STAGGERED = 1;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Divergence { float divergence[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  float sum = 0.0;
  for (int d = 0; d < 3; ++d) {
    if (STAGGERED != 0) {
      const ivec3 up = c + unitStep(d);
      sum += (inGrid(up) ? valueAt(velocity, d, up) : 0.0) - valueAt(velocity, d, c);
    } else {
      sum += difference(velocity, d, c, d);
    }
  }
  divergence[cellIndex(c)] = sum;
}
