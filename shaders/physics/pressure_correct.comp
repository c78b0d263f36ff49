#version 450
#extension GL_GOOGLE_include_directive : require
// Projection: subtract the pressure gradient from the MAC velocity, face by face. For the lower a-face
// of cell c, between m = c − e_a and c:
//   u_a(c) = 0                          if m or c is an obstacle (closed walls, solid obstacles),
//   u_a(c) = u_a(c) − (p_c − p_m)       else if m or c is fluid (p = 0 outside the fluid),
//   u_a(c) unchanged                    otherwise (both empty).
// Index names and stencil masks in obstacle_flags.glsl (m is neighbour 2a of c); velocity is planar
// [3, nz, ny, nx], masks and pressure are in the solver's padded layout (width ≥ nx).
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer pressure;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { float corrected[]; };
layout(push_constant) uniform Push { ivec3 size; int width; };

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  const int padded = padded_index(c, size, width);
  const uint mask = stencil_mask(masks, padded);
  const float pc = mask_fluid(mask) ? texelFetch(pressure, padded).x : 0.0;
  for (int a = 0; a < 3; ++a) {
    const int lower = 2 * a;
    float u = texelFetch(velocity, a * cells + item).x;
    if (!mask_open(mask) || !neighbour_open(mask, lower)) {
      u = 0.0;
    } else if (mask_fluid(mask) || neighbour_fluid(mask, lower)) {
      const int below = padded + neighbour_offset(lower, ivec3(width, size.yz));
      const float pm = neighbour_fluid(mask, lower) ? texelFetch(pressure, below).x : 0.0;
      u -= pc - pm;
    }
    corrected[a * cells + item] = u;
  }
}
