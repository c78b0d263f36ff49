#version 450
#extension GL_GOOGLE_include_directive : require
// Sources that set the velocity blend it in on the MAC faces they cover: for the lower a-face of c
// (centre p = c + ½ − ½e_a, between m = c − e_a and c, neither an obstacle), in table order,
//   u_a(c) = mix(u_a(c), velocity_s,a, w_s(p))   for each source s with the velocity flag,
// w_s the coverage of inflow_sources.glsl. Other faces are copied. Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "inflow_sources.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer table;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push { ivec3 size; int sources; };

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  const bool open = !is_obstacle(cell_flag(flags, c, size));
  for (int a = 0; a < 3; ++a) {
    float u = texelFetch(velocity, a * cells + item).x;
    if (open && !is_obstacle(cell_flag(flags, c - unit_step(a), size))) {
      const vec3 p = vec3(c) + 0.5 - 0.5 * vec3(unit_step(a));
      for (int i = 0; i < sources; ++i) {
        const Source s = read_source(table, i);
        if (s.setsVelocity) u = mix(u, s.velocity[a], source_coverage(s, p));
      }
    }
    result[a * cells + item] = u;
  }
}
