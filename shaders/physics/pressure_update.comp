#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Conjugate gradients, step along the search direction p with q = A p:
//   x_c = x_old_c + α·p_c,   r_c = r_old_c − α·q_c,   partial[s] = max |r_c| over subgroup s.
// α is read from the scalar buffer (pressure_scalars.glsl); c runs over all cells (p = q = 0 outside
// the fluid, so x and r keep their zeros there), one per invocation of a 3D dispatch like the stencil
// kernels, so that its partials line up with theirs.
#include "obstacle_flags.glsl"
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer solutionOld;
layout(binding = 1) uniform samplerBuffer residualOld;
layout(binding = 2) uniform samplerBuffer direction;
layout(binding = 3) uniform samplerBuffer product;
layout(binding = 4) uniform samplerBuffer scalars;
layout(std430, binding = 5) writeonly buffer Solution { float solution[]; };
layout(std430, binding = 6) writeonly buffer Residual { float residual[]; };
layout(std430, binding = 7) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 size; };

void main() {
  const ivec3 c = dispatch_cell();
  float r = 0.0;
  if (in_grid(c, size)) {
    const int item = cell_index(c, size);
    const float alpha = texelFetch(scalars, SCALAR_ALPHA).x;
    solution[item] = texelFetch(solutionOld, item).x + alpha * texelFetch(direction, item).x;
    r = texelFetch(residualOld, item).x - alpha * texelFetch(product, item).x;
    residual[item] = r;
  }
  STORE_PARTIAL_MAX(partial, 0u, abs(r));
}
