#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// One damped Jacobi sweep of the multigrid preconditioner on one level, A x = rhs:
//   x_new_c = x_c + ω·(rhs_c − (A x)_c) / d_c   at fluid cells c, 0 elsewhere,
//   (A x)_c = Σ over non-obstacle neighbours n of (x_c − x_n),  x_n = 0 unless n is fluid,
//   d_c = number of non-obstacle neighbours.
// MODE (constant_id 3): 0 the first sweep from x = 0 (x_new = ω·rhs/d, x and coarse unused);
// 1 a plain sweep; 2 a sweep after the coarse-grid correction, x_c → x_c + coarse(c / 2) at fluid c
// (piecewise-constant prolongation). WITH_DOT (constant_id 4) = 1 also writes partial[s] = Σ rhs_c·x_new_c
// over subgroup s (the r·z of conjugate gradients; pressure_partials.glsl). Index names and stencil masks in
// obstacle_flags.glsl; coarseSize is the size of the next coarser level.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int WITH_DOT = 0;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer rhs;
layout(binding = 2) uniform samplerBuffer x;
layout(binding = 3) uniform samplerBuffer coarse;
layout(std430, binding = 4) writeonly buffer Solution { float xNew[]; };
layout(std430, binding = 5) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; float omega; ivec3 coarseSize; };

float xAt(ivec3 c, int index) {
  const float value = texelFetch(x, index).x;
  return MODE == 2 ? value + texelFetch(coarse, cell_index(c >> 1, coarseSize)).x : value;
}

void main() {
  const ivec3 c = dispatch_cell();
  float rx = 0.0;
  if (in_grid(c, size)) {
    const int item = cell_index(c, size);
    const uint mask = stencil_mask(masks, item);
    float result = 0.0;
    if (mask_fluid(mask)) {
      const float r = texelFetch(rhs, item).x;
      const float diagonal = float(bitCount((mask >> 2) & 63u));
      float update = r;
      if (MODE != 0) {
        const float xc = xAt(c, item);
        float ax = diagonal * xc;
        for (int n = 0; n < 6; ++n) {
          if (neighbour_fluid(mask, n)) ax -= xAt(c + neighbour_step(n), item + neighbour_offset(n, size));
        }
        update = xc * diagonal + omega * (r - ax);
      } else {
        update = omega * r;
      }
      result = diagonal > 0.0 ? update / diagonal : 0.0;
      rx = r * result;
    }
    xNew[item] = result;
  }
  if (WITH_DOT != 0) STORE_PARTIAL_SUM(partial, 0u, rx);
}
