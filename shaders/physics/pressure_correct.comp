#version 450
#extension GL_GOOGLE_include_directive : require
// Projection: subtract the pressure gradient from the MAC velocity, face by face. For the lower a-face
// of cell c, between m = c − e_a and c:
//   u_a(c) = 0                          if m or c is an obstacle (closed walls, solid obstacles),
//   u_a(c) = u_a(c) − (p_c − p_m)       else if m or c is fluid (p = 0 outside the fluid),
//   u_a(c) unchanged                    otherwise (both empty).
// Index names in obstacle_flags.glsl; velocity is planar [3, nz, ny, nx].
#include "index.glsl"
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer pressure;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { float corrected[]; };
layout(push_constant) uniform Push { ivec3 size; };

void main() {
  const int item = int(flat_index());
  const int cells = cell_count(size);
  if (item >= cells) return;
  const ivec3 c = cell_of(item, size);
  const uint flag = cell_flag(flags, c, size);
  const float pc = is_fluid(flag) ? texelFetch(pressure, item).x : 0.0;
  for (int a = 0; a < 3; ++a) {
    const ivec3 m = c - unit_step(a);
    const uint lowerFlag = cell_flag(flags, m, size);
    float u = texelFetch(velocity, a * cells + item).x;
    if (is_obstacle(flag) || is_obstacle(lowerFlag)) {
      u = 0.0;
    } else if (is_fluid(flag) || is_fluid(lowerFlag)) {
      const float pm = is_fluid(lowerFlag) ? texelFetch(pressure, cell_index(m, size)).x : 0.0;
      u -= pc - pm;
    }
    corrected[a * cells + item] = u;
  }
}
