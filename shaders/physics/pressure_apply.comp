#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Conjugate gradients, new search direction and its image under the Poisson matrix, fused, four cells
// per invocation (multigrid_blocks.glsl):
//   p_c = z_c + β·p_old_c   (0 outside the fluid, as z and p_old are),
//   q_c = (A p)_c = d_c·p_c − Σ_n p_n   at fluid cells, 0 elsewhere,
//   partial[s] = Σ p_c·q_c over the cells of subgroup s (pressure_partials.glsl).
// β is read from the scalar buffer (pressure_scalars.glsl).
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer preconditioned;
layout(binding = 2) uniform samplerBuffer directionOld;
layout(binding = 3) uniform samplerBuffer scalars;
layout(std430, binding = 4) writeonly buffer Direction { vec4 direction[]; };
layout(std430, binding = 5) writeonly buffer Product { vec4 product[]; };
layout(std430, binding = 6) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

void main() {
  const ivec3 b = dispatch_block();
  float pq = 0.0;
  if (block_in_grid(b, blocks)) {
    const int t = block_index(b, blocks);
    const float beta = texelFetch(scalars, SCALAR_BETA).x;
    const vec4 p = texelFetch(preconditioned, t) + beta * texelFetch(directionOld, t);
    const Neighbours z = neighbours(preconditioned, texelFetch(preconditioned, t), b, blocks);
    const Neighbours old = neighbours(directionOld, texelFetch(directionOld, t), b, blocks);
    const uvec4 m = block_masks(masks, t);
    const vec4 q = fluid_lanes(m) * (open_neighbours(m) * p - (neighbour_sum(z) + beta * neighbour_sum(old)));
    direction[t] = p;
    product[t] = q;
    pq = dot(p, q);
  }
  STORE_PARTIAL_SUM(partial, 0u, pq);
}
