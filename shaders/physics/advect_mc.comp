#version 450
#extension GL_GOOGLE_include_directive : require
// MacCormack advection of one plane, correction pass (mantaflow's advectSemiLagrange, order 2,
// clampMode 2), from the prepare pass's firstOrder, trace and bounds:
//   out(c) = mc(c) if the correction is kept, else firstOrder(c)   at interior cells c [+ inflow(c)],
//   out(c) = 0 [+ inflow(c)]                                       on the outer layer,
// with mc as in advect_maccormack.glsl. HAS_INFLOW (constant_id 4) adds the inflow plane.
#include "advect_sampling.glsl"
#include "advect_maccormack.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 4) const int HAS_INFLOW = 0;

layout(binding = 0) uniform samplerBuffer firstOrder;
layout(binding = 1) uniform samplerBuffer trace;   // vec4 texels
layout(binding = 2) uniform samplerBuffer bounds;  // vec4 texels
layout(binding = 3) uniform samplerBuffer inflow;
layout(std430, binding = 4) writeonly buffer Output { float result[]; };

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  const int at = plane * cellCount() + cellIndex(c);
  float value = 0.0;
  if (isInterior(c)) {
    bool kept;
    value = macCormack(firstOrder, c, texelFetch(trace, at), texelFetch(bounds, at), kept);
  }
  if (HAS_INFLOW != 0) value += texelFetch(inflow, at).x;
  result[at] = value;
}
