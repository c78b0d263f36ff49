#version 450
#extension GL_GOOGLE_include_directive : require
// Curl of a cell-centred velocity [3, D, H, W] (gradient_stencil.glsl has ∂ and the index names):
//   ω_x = ∂_y u_z − ∂_z u_y,   ω_y = ∂_z u_x − ∂_x u_z,   ω_z = ∂_x u_y − ∂_y u_x.
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Curl { float curl[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  for (int d = 0; d < 3; ++d) {
    const int a = (d + 1) % 3, b = (d + 2) % 3;  // ω_d = ∂_a u_b − ∂_b u_a
    curl[d * cellCount() + cellIndex(c)] = difference(velocity, b, c, a) - difference(velocity, a, c, b);
  }
}
