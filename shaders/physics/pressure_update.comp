#version 450
#extension GL_GOOGLE_include_directive : require
// Conjugate gradients, step along the search direction p with q = A p:
//   x_c = x_old_c + α·p_c,   r_c = r_old_c − α·q_c,   partial[g] = max |r_c| over workgroup g.
// α is read from the scalar buffer (pressure_scalars.glsl); c runs over all cells (p = q = 0 outside
// the fluid, so x and r keep their zeros there).
#include "index.glsl"
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
layout(push_constant) uniform Push { uint cells; };

void main() {
  const uint item = flat_index();
  float r = 0.0;
  if (item < cells) {
    const float alpha = texelFetch(scalars, SCALAR_ALPHA).x;
    solution[item] = texelFetch(solutionOld, int(item)).x + alpha * texelFetch(direction, int(item)).x;
    r = texelFetch(residualOld, int(item)).x - alpha * texelFetch(product, int(item)).x;
    residual[item] = r;
  }
  const float maxR = workgroup_max(abs(r));
  if (gl_LocalInvocationIndex == 0u) partial[workgroup_slot()] = maxR;
}
