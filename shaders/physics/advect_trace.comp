#version 450
#extension GL_GOOGLE_include_directive : require
// Departure points of one plane and the plane's reach, for the gather-form adjoints:
//   departure(c) = (c + ½ − v(c)·dt, 1) at interior cells c, (0, 0, 0, 0) on the outer layer;
//   o(c) = b(c) − c, the offset of the clamped stencil base b of c's departure point;
//   reach[8·plane + d]     = REACH_BIAS + max over interior c of  o_d(c),
//   reach[8·plane + 4 + d] = REACH_BIAS + max over interior c of −o_d(c),
// reduced per workgroup in shared memory, then atomicMax into a zero-filled buffer (the bias keeps
// every stored value positive, so zero is the identity). Index names as in advect_sampling.glsl.
#include "index.glsl"
#include "advect_sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

const int REACH_BIAS = 1 << 20;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Departure { vec4 departure[]; };
layout(std430, binding = 2) buffer Reach { int reach[]; };

shared ivec3 highest[gl_WorkGroupSize.x];
shared ivec3 lowest[gl_WorkGroupSize.x];

void main() {
  const int item = int(flat_index());
  const uint local = gl_LocalInvocationID.x;
  ivec3 high = ivec3(-REACH_BIAS);
  ivec3 low = ivec3(-REACH_BIAS);
  if (item < cellCount()) {
    const ivec3 c = cellOf(item);
    vec4 point = vec4(0.0);
    if (isInterior(c)) {
      point = vec4(departurePoint(c, traceVelocity(velocity, c), dt), 1.0);
      const ivec3 offset = stencilAt(point.xyz).base - c;
      high = offset;
      low = -offset;
    }
    departure[plane * cellCount() + item] = point;
  }
  highest[local] = high;
  lowest[local] = low;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) {
      highest[local] = max(highest[local], highest[local + half_]);
      lowest[local] = max(lowest[local], lowest[local + half_]);
    }
    barrier();
  }
  if (local == 0u && highest[0].x > -REACH_BIAS) {
    for (int d = 0; d < 3; ++d) {
      atomicMax(reach[8 * plane + d], REACH_BIAS + highest[0][d]);
      atomicMax(reach[8 * plane + 4 + d], REACH_BIAS + lowest[0][d]);
    }
  }
}
