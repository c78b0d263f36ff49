#version 450
#extension GL_GOOGLE_include_directive : require
// MacCormack advection of one plane, first pass: the semi-Lagrangian value and what the correction
// pass needs per cell (advect_maccormack.glsl has the rules, advect_sampling.glsl the index names):
//   firstOrder(c) = trilinear(field, c + ½ − v(c)·dt) at interior cells, 0 on the outer layer;
//   trace(c)      = (v(c), field(c));
//   bounds(c)     = (low, high, firstOrder(c), 0), the range a correction must stay in (empty
//                   where none can stand, and on the outer layer).
#include "advect_sampling.glsl"
#include "advect_maccormack.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer field;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer FirstOrder { float firstOrder[]; };
layout(std430, binding = 4) writeonly buffer Trace { vec4 trace[]; };
layout(std430, binding = 5) writeonly buffer BoundsNonFinite { vec4 bounds[]; };  // ±inf: an empty range

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  const int at = plane * cellCount() + cellIndex(c);
  float forward = 0.0;
  vec4 traced = vec4(0.0);
  vec2 range = vec2(infinity(), -infinity());
  if (isInterior(c)) {
    const vec3 v = traceVelocity(velocity, c);
    float corner[8];
    const Stencil s = stencilAt(departurePoint(c, v, dt));
    fetchCorners(field, plane * cellCount(), s, corner);
    forward = trilinear(corner, s);
    range = correctionRange(masks, field, c, v, s, corner);
    traced = vec4(v, texelFetch(field, at).x);
  }
  firstOrder[at] = forward;
  trace[at] = traced;
  bounds[at] = vec4(range, forward, 0.0);
}
