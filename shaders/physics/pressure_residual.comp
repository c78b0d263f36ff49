#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Start of the pressure solve: right-hand side and initial residual of the Poisson equation A p = b,
//   b_c = −div(u)_c = −Σ_a (u_a(c + e_a) − u_a(c)),  a face touching an obstacle counting as 0,
//   (A p)_c = Σ over non-obstacle neighbours n of (p_c − p_n),  p_n = 0 in empty (open) cells,
//   residual_c = b_c − (A p0)_c  at fluid cells, 0 elsewhere,
// and per subgroup s (pressure_partials.glsl): partial[s] = max |b|, partial[count + s] = max |residual|,
// partial[2·count + s] = Σ residual over its cells, count = the number of subgroups in the dispatch.
// Index names and stencil masks in obstacle_flags.glsl; p0 is the initial guess. Masks, p0 and the
// residual are in the solver's padded layout (width ≥ nx, multigrid_blocks.glsl), the velocity is not;
// padding cells are left alone (they stay 0).
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer velocity;
layout(binding = 2) uniform samplerBuffer pressure;
layout(std430, binding = 3) writeonly buffer Residual { float residual[]; };
layout(std430, binding = 4) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; int width; uint count; };

void main() {
  const ivec3 c = dispatch_cell();
  const int cells = cell_count(size);
  float b = 0.0;
  float r = 0.0;
  if (in_grid(c, size)) {
    const int item = cell_index(c, size);
    const int padded = padded_index(c, size, width);
    const uint mask = stencil_mask(masks, padded);
    if (mask_fluid(mask)) {
      const float pc = texelFetch(pressure, padded).x;
      float divergence = 0.0;
      float laplacian = 0.0;
      for (int n = 0; n < 6; ++n) {
        if (!neighbour_open(mask, n)) continue;
        const int axis = n >> 1;
        const bool upper = (n & 1) == 1;
        const float face = texelFetch(velocity, axis * cells + item + (upper ? neighbour_offset(n, size) : 0)).x;
        divergence += upper ? face : -face;
        const int neighbour = padded + neighbour_offset(n, ivec3(width, size.yz));
        laplacian += pc - (neighbour_fluid(mask, n) ? texelFetch(pressure, neighbour).x : 0.0);
      }
      b = -divergence;
      r = b - laplacian;
    }
    residual[padded] = r;
  }
  STORE_PARTIAL_MAX(partial, 0u, abs(b));
  STORE_PARTIAL_MAX(partial, count, abs(r));
  STORE_PARTIAL_SUM(partial, 2u * count, r);
}
