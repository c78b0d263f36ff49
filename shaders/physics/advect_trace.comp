#version 450
#extension GL_GOOGLE_include_directive : require
// Departure stencils of one plane, for the gather-form adjoints. Per cell c:
//   departure(c) = (q, slopes) at interior cells, (0, 0, 0, −1) elsewhere: q = b + w1 is the clamped
//     stencil position (base b = min(trunc(q), n − 2), upper weights w1 = q − b, advect_sampling.glsl)
//     of c's departure point c + ½ − v(c)·dt, slopes = Σ_d 2^d·slope_d (axes where it is not clamped).
#include "advect_sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Departure { vec4 departure[]; };

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  vec4 stencil = vec4(0.0, 0.0, 0.0, -1.0);
  if (isInterior(c)) {
    const Stencil s = stencilAt(departurePoint(c, traceVelocity(velocity, c), dt));
    stencil = vec4(vec3(s.base) + s.w1, dot(s.slope, vec3(1.0, 2.0, 4.0)));
  }
  departure[plane * cellCount() + cellIndex(c)] = stencil;
}
