#version 450
#extension GL_GOOGLE_include_directive : require
// pressure_correct.comp for grids whose width is a multiple of 4 (the padded layout is then the user's),
// four cells per invocation (multigrid_blocks.glsl). With p = 0 outside the fluid, for the lower a-face
// of c (m = c − e_a):
//   u_a(c) = open(c)·open(m)·(u_a(c) − (p_c − p_m))
// (0 if either cell is an obstacle; unchanged between two empty cells, where p_c = p_m = 0).
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer pressure;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { vec4 corrected[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

vec4 open_lanes(uvec4 m, int n) { return vec4((m >> uint(2 + n)) & uvec4(1u)); }

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const int plane = plane_texels(blocks);
  const uvec4 m = block_masks(masks, t);
  const vec4 self = vec4((m & uvec4(MASK_OPEN)) >> 1u);
  const vec4 pc = texelFetch(pressure, t);
  const Lower pm = lower_neighbours(pressure, t, pc, b, blocks, 0.0);
  corrected[t] = self * open_lanes(m, 0) * (texelFetch(velocity, t) - (pc - pm.x));
  corrected[plane + t] = self * open_lanes(m, 2) * (texelFetch(velocity, plane + t) - (pc - pm.y));
  corrected[2 * plane + t] = self * open_lanes(m, 4) * (texelFetch(velocity, 2 * plane + t) - (pc - pm.z));
}
