#version 450
#extension GL_GOOGLE_include_directive : require
// MacCormack advection of one plane, second pass (mantaflow's advectSemiLagrange, order 2,
// clampMode 2), given the first-order pass fwd = SL(field, dt) from advect_sl:
//   out(c) = mc(c) if the correction is kept, else fwd(c)   at interior cells c [+ inflow(c)],
//   out(c) = 0 [+ inflow(c)]                                on the outer layer,
// with mc and the clamp as in advect_maccormack.glsl. HAS_INFLOW (constant_id 3) adds the inflow.
#include "index.glsl"
#include "advect_sampling.glsl"
#include "advect_maccormack.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int HAS_INFLOW = 0;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer field;
layout(binding = 2) uniform samplerBuffer firstOrder;
layout(binding = 3) uniform samplerBuffer velocity;
layout(binding = 4) uniform samplerBuffer inflow;
layout(std430, binding = 5) writeonly buffer Output { float result[]; };

void main() {
  const int item = int(flat_index());
  if (item >= cellCount()) return;
  const ivec3 c = cellOf(item);
  const int at = plane * cellCount() + item;
  float value = 0.0;
  if (isInterior(c)) {
    bool kept;
    value = macCormack(flags, field, firstOrder, c, traceVelocity(velocity, c), kept);
  }
  if (HAS_INFLOW != 0) value += texelFetch(inflow, at).x;
  result[at] = value;
}
