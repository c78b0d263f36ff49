#version 450
#extension GL_GOOGLE_include_directive : require
// Conjugate gradients, new search direction and its image under the Poisson matrix, fused:
//   p_c = z_c + β·p_old_c                     at fluid cells, 0 elsewhere,
//   q_c = (A p)_c = Σ over non-obstacle neighbours n of (p_c − p_n)   (p_n = 0 unless n is fluid),
//   partial[g] = Σ p_c·q_c over the cells of workgroup g.
// β is read from the scalar buffer (pressure_scalars.glsl); index names in obstacle_flags.glsl.
#include "index.glsl"
#include "obstacle_flags.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer flags;
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
  const int item = int(flat_index());
  float pq = 0.0;
  if (item < cell_count(size)) {
    const ivec3 c = cell_of(item, size);
    float p = 0.0;
    float q = 0.0;
    if (is_fluid(cell_flag(flags, c, size))) {
      const float beta = texelFetch(scalars, SCALAR_BETA).x;
      p = directionAt(item, beta);
      for (int a = 0; a < 3; ++a) {
        for (int side = -1; side <= 1; side += 2) {
          const ivec3 n = c + side * unit_step(a);
          const uint flag = cell_flag(flags, n, size);
          if (!is_obstacle(flag)) q += p - (is_fluid(flag) ? directionAt(cell_index(n, size), beta) : 0.0);
        }
      }
    }
    direction[item] = p;
    product[item] = q;
    pq = p * q;
  }
  const float sum = workgroup_sum(pq);
  if (gl_LocalInvocationIndex == 0u) partial[workgroup_slot()] = sum;
}
