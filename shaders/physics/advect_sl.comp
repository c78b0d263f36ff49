#version 450
#extension GL_GOOGLE_include_directive : require
// Semi-Lagrangian advection of one plane (mantaflow's advectSemiLagrange, order 1):
//   out(c) = trilinear(field, c + ½ − v(c)·dt) [+ inflow(c)]   at interior cells c,
//   out(c) = 0 [+ inflow(c)]                                   on the outer layer,
// v(c) the plane's trace velocity, lookups clamped to cell centres (advect_sampling.glsl has the
// index names). HAS_INFLOW (constant_id 4) adds the inflow plane.
#include "advect_sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 4) const int HAS_INFLOW = 0;

layout(binding = 0) uniform samplerBuffer field;
layout(binding = 1) uniform samplerBuffer velocity;
layout(binding = 2) uniform samplerBuffer inflow;
layout(std430, binding = 3) writeonly buffer Output { float result[]; };

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  const int item = cellIndex(c);
  const int at = plane * cellCount() + item;
  float value = 0.0;
  if (isInterior(c)) {
    float corner[8];
    const Stencil s = stencilAt(departurePoint(c, traceVelocity(velocity, c), dt));
    fetchCorners(field, plane * cellCount(), s, corner);
    value = trilinear(corner, s);
  }
  if (HAS_INFLOW != 0) value += texelFetch(inflow, at).x;
  result[at] = value;
}
