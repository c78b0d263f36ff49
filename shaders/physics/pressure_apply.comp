#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Conjugate gradients, new search direction and its image under the Poisson matrix, fused:
//   p_c = z_c + β·p_old_c                     at fluid cells, 0 elsewhere,
//   q_c = (A p)_c = Σ over non-obstacle neighbours n of (p_c − p_n)   (p_n = 0 unless n is fluid),
//   partial[s] = Σ p_c·q_c over the cells of subgroup s (pressure_partials.glsl).
// β is read from the scalar buffer (pressure_scalars.glsl); index names and stencil masks in
// obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer preconditioned;
layout(binding = 2) uniform samplerBuffer directionOld;
layout(binding = 3) uniform samplerBuffer scalars;
layout(std430, binding = 4) writeonly buffer Direction { float direction[]; };
layout(std430, binding = 5) writeonly buffer Product { float product[]; };
layout(std430, binding = 6) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; };

float directionAt(int index, float beta) {
  return texelFetch(preconditioned, index).x + beta * texelFetch(directionOld, index).x;
}

void main() {
  const ivec3 c = dispatch_cell();
  float pq = 0.0;
  if (in_grid(c, size)) {
    const int item = cell_index(c, size);
    const uint mask = stencil_mask(masks, item);
    float p = 0.0;
    float q = 0.0;
    if (mask_fluid(mask)) {
      const float beta = texelFetch(scalars, SCALAR_BETA).x;
      p = directionAt(item, beta);
      for (int n = 0; n < 6; ++n) {
        if (!neighbour_open(mask, n)) continue;
        q += p - (neighbour_fluid(mask, n) ? directionAt(item + neighbour_offset(n, size), beta) : 0.0);
      }
    }
    direction[item] = p;
    product[item] = q;
    pq = p * q;
  }
  STORE_PARTIAL_SUM(partial, 0u, pq);
}
