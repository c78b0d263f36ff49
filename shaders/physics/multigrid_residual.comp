#version 450
#extension GL_GOOGLE_include_directive : require
// Residual of one multigrid level, four cells per invocation (multigrid_blocks.glsl):
//   residual_c = rhs_c − (A x)_c = rhs_c − d_c·x_c + Σ_n x_n   at fluid cells, 0 elsewhere.
// Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer rhs;
layout(binding = 2) uniform samplerBuffer x;
layout(std430, binding = 3) writeonly buffer Residual { vec4 residual[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const uvec4 m = block_masks(masks, t);
  const vec4 xc = texelFetch(x, t);
  const vec4 ax = open_neighbours(m) * xc - neighbour_sum(neighbours(x, xc, b, blocks));
  residual[t] = fluid_lanes(m) * (texelFetch(rhs, t) - ax);
}
