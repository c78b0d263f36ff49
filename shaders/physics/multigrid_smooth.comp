#version 450
#extension GL_GOOGLE_include_directive : require
// One damped Jacobi sweep of the multigrid preconditioner on one level, A x = rhs:
//   x_new_c = x_c + ω·(rhs_c − (A x)_c) / d_c   at fluid cells c, 0 elsewhere,
//   (A x)_c = Σ over non-obstacle neighbours n of (x_c − x_n),  x_n = 0 unless n is fluid,
//   d_c = number of non-obstacle neighbours.
// MODE (constant_id 3): 0 the first sweep from x = 0 (x_new = ω·rhs/d, x and coarse unused);
// 1 a plain sweep; 2 a sweep after the coarse-grid correction, x_c → x_c + coarse(c / 2) at fluid c
// (piecewise-constant prolongation). WITH_DOT (constant_id 4) = 1 also writes partial[g] = Σ rhs_c·x_new_c
// over workgroup g (the r·z of conjugate gradients). Index names in obstacle_flags.glsl; coarseSize is
// the size of the next coarser level.
#include "index.glsl"
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int WITH_DOT = 0;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer rhs;
layout(binding = 2) uniform samplerBuffer x;
layout(binding = 3) uniform samplerBuffer coarse;
layout(std430, binding = 4) writeonly buffer Solution { float xNew[]; };
layout(std430, binding = 5) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; float omega; ivec3 coarseSize; };

float xAt(ivec3 c) {
  const float value = texelFetch(x, cell_index(c, size)).x;
  return MODE == 2 ? value + texelFetch(coarse, cell_index(c / 2, coarseSize)).x : value;
}

void main() {
  const int item = int(flat_index());
  float rx = 0.0;
  if (item < cell_count(size)) {
    const ivec3 c = cell_of(item, size);
    float result = 0.0;
    if (is_fluid(cell_flag(flags, c, size))) {
      const float r = texelFetch(rhs, item).x;
      const float xc = MODE == 0 ? 0.0 : xAt(c);
      float diagonal = 0.0;
      float ax = 0.0;
      for (int a = 0; a < 3; ++a) {
        for (int side = -1; side <= 1; side += 2) {
          const ivec3 n = c + side * unit_step(a);
          const uint flag = cell_flag(flags, n, size);
          if (is_obstacle(flag)) continue;
          diagonal += 1.0;
          if (MODE != 0) ax += xc - (is_fluid(flag) ? xAt(n) : 0.0);
        }
      }
      result = diagonal > 0.0 ? xc + omega * (r - ax) / diagonal : 0.0;
      rx = r * result;
    }
    xNew[item] = result;
  }
  if (WITH_DOT != 0) {
    const float sum = workgroup_sum(rx);
    if (gl_LocalInvocationIndex == 0u) partial[workgroup_slot()] = sum;
  }
}
