#version 450
#extension GL_GOOGLE_include_directive : require
// Sources that set the velocity blend it in, in place, on the MAC faces they cover: for the lower a-face
// of c (centre p = c + ½ − ½e_a, between m = c − e_a and c, neither an obstacle), in table order,
//   u_a(c) = mix(u_a(c), velocity_s,a, w_s(p))   for each source s with the velocity flag,
// w_s the coverage of inflow_sources.glsl. The dispatch covers only the box of cells low + gid that
// holds the velocity sources (computed by the host); other faces keep their value. Index names in
// obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "inflow_sources.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer table;
layout(std430, binding = 2) buffer Velocity { float velocity[]; };
layout(push_constant) uniform Push {
  ivec3 size;
  int sources;
  ivec3 low;
};

void main() {
  const ivec3 c = low + dispatch_cell();
  if (!in_grid(c, size) || is_obstacle(cell_flag(flags, c, size))) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  // Faces whose other cell is an obstacle keep their value (weight 0).
  const vec3 open = vec3(is_obstacle(cell_flag(flags, c - ivec3(1, 0, 0), size)) ? 0.0 : 1.0,
                         is_obstacle(cell_flag(flags, c - ivec3(0, 1, 0), size)) ? 0.0 : 1.0,
                         is_obstacle(cell_flag(flags, c - ivec3(0, 0, 1), size)) ? 0.0 : 1.0);
  vec3 u = vec3(velocity[item], velocity[cells + item], velocity[2 * cells + item]);
  const vec3 centre = vec3(c) + 0.5;
  for (int i = 0; i < sources; ++i) {
    const Source s = read_source(table, i);
    if (!s.setsVelocity) continue;
    const vec3 w = open * vec3(source_coverage(s, centre - vec3(0.5, 0.0, 0.0)),
                               source_coverage(s, centre - vec3(0.0, 0.5, 0.0)),
                               source_coverage(s, centre - vec3(0.0, 0.0, 0.5)));
    u = mix(u, s.velocity, w);
  }
  velocity[item] = u.x;
  velocity[cells + item] = u.y;
  velocity[2 * cells + item] = u.z;
}
