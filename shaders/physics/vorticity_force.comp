#version 450
#extension GL_GOOGLE_include_directive : require
// Vorticity confinement force at cell centres (mantaflow's KnConfForce) from the vorticity planes of
// vorticity_field.comp, [4, nz, ny, nx] = ω_x, ω_y, ω_z, |ω|:
//   N(c) = normalise(½(|ω|(c + e_a) − |ω|(c − e_a)))_a   (0 where the gradient vanishes),
//   F(c) = ε·N(c) × ω(c) at interior cells, 0 on the outer layer; output planar [3, nz, ny, nx].
// force_field.comp then applies F to the MAC faces. Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer vorticity;
layout(std430, binding = 1) writeonly buffer Force { float force[]; };
layout(push_constant) uniform Push { ivec3 size; float strength; };

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  vec3 result = vec3(0.0);
  if (all(greaterThan(c, ivec3(0))) && all(lessThan(c, size - 1))) {
    const int magnitude = 3 * cells;
    const int row = size.x, slice = size.x * size.y;
    const vec3 gradient = 0.5 * vec3(texelFetch(vorticity, magnitude + item + 1).x - texelFetch(vorticity, magnitude + item - 1).x,
                                     texelFetch(vorticity, magnitude + item + row).x - texelFetch(vorticity, magnitude + item - row).x,
                                     texelFetch(vorticity, magnitude + item + slice).x - texelFetch(vorticity, magnitude + item - slice).x);
    const float norm = length(gradient);
    if (norm > 1e-20) {
      const vec3 omega = vec3(texelFetch(vorticity, item).x, texelFetch(vorticity, cells + item).x,
                              texelFetch(vorticity, 2 * cells + item).x);
      result = strength * cross(gradient / norm, omega);
    }
  }
  force[item] = result.x;
  force[cells + item] = result.y;
  force[2 * cells + item] = result.z;
}
