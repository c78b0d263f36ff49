#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Conjugate gradients, step along the search direction p with q = A p, four cells per invocation:
//   x_c = x_old_c + α·p_c,   r_c = r_old_c − α·q_c,   partial[s] = max |r_c| over subgroup s.
// α is read from the scalar buffer (pressure_scalars.glsl); p = q = 0 outside the fluid, so x and r keep
// their zeros there. Blocks in multigrid_blocks.glsl (the same dispatch as the stencil kernels, so that
// the partials line up).
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer solutionOld;
layout(binding = 1) uniform samplerBuffer residualOld;
layout(binding = 2) uniform samplerBuffer direction;
layout(binding = 3) uniform samplerBuffer product;
layout(binding = 4) uniform samplerBuffer scalars;
layout(std430, binding = 5) writeonly buffer Solution { vec4 solution[]; };
layout(std430, binding = 6) writeonly buffer Residual { vec4 residual[]; };
layout(std430, binding = 7) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

void main() {
  const ivec3 b = dispatch_block();
  float maxR = 0.0;
  if (block_in_grid(b, blocks)) {
    const int t = block_index(b, blocks);
    const float alpha = texelFetch(scalars, SCALAR_ALPHA).x;
    solution[t] = texelFetch(solutionOld, t) + alpha * texelFetch(direction, t);
    const vec4 r = texelFetch(residualOld, t) - alpha * texelFetch(product, t);
    residual[t] = r;
    const vec4 a = abs(r);
    maxR = max(max(a.x, a.y), max(a.z, a.w));
  }
  STORE_PARTIAL_MAX(partial, 0u, maxR);
}
