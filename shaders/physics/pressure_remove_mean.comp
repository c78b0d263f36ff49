#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// In a closed domain (no empty cell) the Poisson matrix is singular with the constants as null space, and
// b = −div u sums to zero only up to rounding; the solve removes that part from the initial residual,
// four cells per invocation (multigrid_blocks.glsl):
//   r_c = r_old_c − mean_r   at fluid cells (0 elsewhere),   partial[s] = max |r_c| over subgroup s,
// mean_r from the scalar buffer (pressure_scalars.glsl).
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer residualOld;
layout(binding = 2) uniform samplerBuffer scalars;
layout(std430, binding = 3) writeonly buffer Residual { vec4 residual[]; };
layout(std430, binding = 4) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

void main() {
  const ivec3 b = dispatch_block();
  float maxR = 0.0;
  if (block_in_grid(b, blocks)) {
    const int t = block_index(b, blocks);
    const vec4 r = fluid_lanes(block_masks(masks, t)) * (texelFetch(residualOld, t) - texelFetch(scalars, SCALAR_MEAN_R).x);
    residual[t] = r;
    const vec4 a = abs(r);
    maxR = max(max(a.x, a.y), max(a.z, a.w));
  }
  STORE_PARTIAL_MAX(partial, 0u, maxR);
}
