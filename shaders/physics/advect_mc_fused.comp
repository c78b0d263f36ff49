#version 450
#extension GL_GOOGLE_include_directive : require
// MacCormack advection of one plane without a cache for the adjoint (the simulator's path): the
// correction pass recomputes the trace and the clamp range instead of reading them, so the first pass
// is plain semi-Lagrangian (advect_sl.comp) and nothing but values is written:
//   out(c) = mc(c) if the correction is kept, else firstOrder(c)   at interior cells c [+ inflow(c)],
//   out(c) = 0 [+ inflow(c)]                                       on the outer layer,
// mc, the range and the rules as in advect_maccormack.glsl; the same values as advect_mc_prepare.comp
// followed by advect_mc.comp. HAS_INFLOW (constant_id 4) adds the inflow plane.
#include "advect_sampling.glsl"
#include "advect_maccormack.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 4) const int HAS_INFLOW = 0;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer field;
layout(binding = 2) uniform samplerBuffer velocity;
layout(binding = 3) uniform samplerBuffer firstOrder;
layout(binding = 4) uniform samplerBuffer inflow;
layout(std430, binding = 5) writeonly buffer Output { float result[]; };

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  const int at = plane * cellCount() + cellIndex(c);
  float value = 0.0;
  if (isInterior(c)) {
    const vec3 v = traceVelocity(velocity, c);
    float corner[8];
    const Stencil s = stencilAt(departurePoint(c, v, dt));
    fetchCorners(field, plane * cellCount(), s, corner);
    const float forward = texelFetch(firstOrder, at).x;
    const vec2 range = correctionRange(masks, field, c, v, s, corner);
    bool kept;
    value = macCormack(firstOrder, c, vec4(v, texelFetch(field, at).x), vec4(range, forward, 0.0), kept);
  }
  if (HAS_INFLOW != 0) value += texelFetch(inflow, at).x;
  result[at] = value;
}
