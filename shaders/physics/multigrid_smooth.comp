#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// One damped Jacobi sweep of the multigrid preconditioner on one level, A x = rhs, four cells per
// invocation (multigrid_blocks.glsl):
//   x_new_c = x_c + ω·(rhs_c − (A x)_c) / d_c   at fluid cells c, 0 elsewhere,
//   (A x)_c = d_c·x_c − Σ_n x_n,  d_c = number of non-obstacle neighbours.
// FIRST (constant_id 3) = 1: the first sweep from x = 0, x_new = ω·rhs/d (x unread). WITH_DOT (constant_id
// 4) = 1 also writes partial[s] = Σ rhs_c·x_new_c over subgroup s (conjugate gradients' r·z;
// pressure_partials.glsl). Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int FIRST = 0;
layout(constant_id = 4) const int WITH_DOT = 0;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer rhs;
layout(binding = 2) uniform samplerBuffer x;
layout(std430, binding = 3) writeonly buffer Solution { vec4 xNew[]; };
layout(std430, binding = 4) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 blocks; float omega; };

void main() {
  const ivec3 b = dispatch_block();
  float rx = 0.0;
  if (block_in_grid(b, blocks)) {
    const int t = block_index(b, blocks);
    const uvec4 m = block_masks(masks, t);
    const vec4 r = texelFetch(rhs, t);
    const vec4 d = open_neighbours(m);
    vec4 update = omega * r;
    if (FIRST == 0) {
      const vec4 xc = texelFetch(x, t);
      update = d * xc + omega * (r - (d * xc - neighbour_sum(neighbours(x, xc, b, blocks))));
    }
    const vec4 result = fluid_lanes(m) * mix(update / max(d, vec4(1.0)), vec4(0.0), equal(d, vec4(0.0)));
    xNew[t] = result;
    rx = dot(r, result);
  }
  if (WITH_DOT != 0) STORE_PARTIAL_SUM(partial, 0u, rx);
}
