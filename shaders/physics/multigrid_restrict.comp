#version 450
#extension GL_GOOGLE_include_directive : require
// Restriction of a fine level's residual to the next coarser level, four coarse cells per invocation:
//   coarseRhs_C = γ · Σ over the children f = 2C + (0|1, 0|1, 0|1) of residual_f   at fluid coarse cells,
// 0 elsewhere (the residual is 0 outside the fluid and past the fine grid). γ = ½ matches a coarse operator
// with the fine stencil's integer weights: the 2h Laplacian is ¼ of it and the rhs an average of 8.
// Coarse block (h, J, K) covers fine texels 2h, 2h+1 of fine rows (2J|2J+1, 2K|2K+1). Blocks in
// multigrid_blocks.glsl.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer residual;
layout(binding = 1) uniform samplerBuffer coarseMasks;
layout(std430, binding = 2) writeonly buffer CoarseRhs { vec4 coarseRhs[]; };
layout(push_constant) uniform Push { ivec3 blocks; float gamma; ivec3 coarseBlocks; };

void main() {
  const ivec3 c = dispatch_block();
  if (!block_in_grid(c, coarseBlocks)) return;
  vec4 sum = vec4(0.0);
  for (int child = 0; child < 4; ++child) {
    const ivec3 row = ivec3(0, 2 * c.y + (child & 1), 2 * c.z + (child >> 1));
    if (row.y >= blocks.y || row.z >= blocks.z) continue;
    for (int half_ = 0; half_ < 2; ++half_) {
      const ivec3 f = ivec3(2 * c.x + half_, row.y, row.z);
      if (f.x >= blocks.x) continue;
      const vec4 r = texelFetch(residual, block_index(f, blocks));
      const vec2 pairs = r.xz + r.yw;  // coarse cells 4h + 2·half_ and 4h + 2·half_ + 1
      if (half_ == 0) sum.xy += pairs;
      else sum.zw += pairs;
    }
  }
  const int t = block_index(c, coarseBlocks);
  coarseRhs[t] = fluid_lanes(block_masks(coarseMasks, t)) * gamma * sum;
}
