#version 450
#extension GL_GOOGLE_include_directive : require
// A cell-centred acceleration field f (planar [3, nz, ny, nx]) applied to the MAC velocity, mantaflow's
// KnApplyForceField (additive): on every face that takes a force (force_faces.glsl), the lower a-face
// of c with m = c − e_a,
//   u_a(c) += dt·½(f_a(c) + f_a(m)).
// Other faces are copied. Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "force_faces.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer force;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push { ivec3 size; float dt; };

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  const uint flag = cell_flag(flags, c, size);
  for (int a = 0; a < 3; ++a) {
    const ivec3 m = c - unit_step(a);
    float u = texelFetch(velocity, a * cells + item).x;
    if (force_acts(flag, cell_flag(flags, m, size)))
      u += dt * 0.5 * (texelFetch(force, a * cells + item).x + texelFetch(force, a * cells + cell_index(m, size)).x);
    result[a * cells + item] = u;
  }
}
