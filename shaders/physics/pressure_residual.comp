#version 450
#extension GL_GOOGLE_include_directive : require
// Start of the pressure solve: right-hand side and initial residual of the Poisson equation A p = b,
//   b_c = −div(u)_c = −Σ_a (u_a(c + e_a) − u_a(c)),  a face touching an obstacle counting as 0,
//   (A p)_c = Σ over non-obstacle neighbours n of (p_c − p_n),  p_n = 0 in empty (open) cells,
//   residual_c = b_c − (A p0)_c  at fluid cells, 0 elsewhere,
// and per workgroup g: partial[g] = max |b|, partial[groups + g] = max |residual| over its cells.
// Index names in obstacle_flags.glsl; p0 is the initial guess (the previous step's pressure).
#include "index.glsl"
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer velocity;
layout(binding = 2) uniform samplerBuffer pressure;
layout(std430, binding = 3) writeonly buffer Residual { float residual[]; };
layout(std430, binding = 4) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; uint groups; };

void main() {
  const int item = int(flat_index());
  const int cells = cell_count(size);
  float b = 0.0;
  float r = 0.0;
  if (item < cells) {
    const ivec3 c = cell_of(item, size);
    if (is_fluid(cell_flag(flags, c, size))) {
      const float pc = texelFetch(pressure, item).x;
      float divergence = 0.0;
      float laplacian = 0.0;
      for (int a = 0; a < 3; ++a) {
        const ivec3 lower = c - unit_step(a);
        const ivec3 upper = c + unit_step(a);
        const uint lowerFlag = cell_flag(flags, lower, size);
        const uint upperFlag = cell_flag(flags, upper, size);
        if (!is_obstacle(lowerFlag)) {
          divergence -= texelFetch(velocity, a * cells + item).x;
          laplacian += pc - (is_fluid(lowerFlag) ? texelFetch(pressure, cell_index(lower, size)).x : 0.0);
        }
        if (!is_obstacle(upperFlag)) {
          const int upperIndex = cell_index(upper, size);
          divergence += texelFetch(velocity, a * cells + upperIndex).x;
          laplacian += pc - (is_fluid(upperFlag) ? texelFetch(pressure, upperIndex).x : 0.0);
        }
      }
      b = -divergence;
      r = b - laplacian;
    }
    residual[item] = r;
  }
  const float maxB = workgroup_max(abs(b));
  const float maxR = workgroup_max(abs(r));
  if (gl_LocalInvocationIndex == 0u) {
    partial[workgroup_slot()] = maxB;
    partial[groups + workgroup_slot()] = maxR;
  }
}
