#version 450
#extension GL_GOOGLE_include_directive : require
// Coarse-grid correction, piecewise constant, four fine cells per invocation:
//   x_new_c = x_c + coarse(c / 2)   at fluid cells c, 0 elsewhere.
// Fine block g holds cells 4g … 4g+3, whose parents 2g, 2g, 2g+1, 2g+1 lie in coarse texel g/2 at lanes
// 2·(g mod 2) and 2·(g mod 2) + 1. Blocks in multigrid_blocks.glsl.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer x;
layout(binding = 2) uniform samplerBuffer coarse;
layout(std430, binding = 3) writeonly buffer Solution { vec4 xNew[]; };
layout(push_constant) uniform Push { ivec3 blocks; int unused; ivec3 coarseBlocks; };

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const vec4 parent = texelFetch(coarse, block_index(ivec3(b.x >> 1, b.y >> 1, b.z >> 1), coarseBlocks));
  const vec2 pair = (b.x & 1) == 0 ? parent.xy : parent.zw;
  xNew[t] = fluid_lanes(block_masks(masks, t)) * (texelFetch(x, t) + pair.xxyy);
}
