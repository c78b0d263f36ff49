#version 450
#extension GL_GOOGLE_include_directive : require
// The plane's overall reach from its tiles' (advect_tile_reach): one workgroup of G invocations,
// each taking every G-th tile, then a tree in shared memory (G a power of two):
//   reach[entry tiles][k] = max over tiles U of reach[U][k]   for k = 0..2, 4..6
// (stored values are biased and 0 means empty, so the plain maximum is the union).
#include "advect_sampling.glsl"
#include "advect_tiles.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(std430, binding = 0) buffer Reach { int reach[]; };

shared ivec3 highest[gl_WorkGroupSize.x];
shared ivec3 lowest[gl_WorkGroupSize.x];

void main() {
  const uint local = gl_LocalInvocationID.x;
  ivec3 high = ivec3(0);
  ivec3 low = ivec3(0);
  for (int tile = int(local); tile < tileCount(); tile += int(gl_WorkGroupSize.x)) {
    const int at = reachEntry(tile);
    high = max(high, ivec3(reach[at], reach[at + 1], reach[at + 2]));
    low = max(low, ivec3(reach[at + 4], reach[at + 5], reach[at + 6]));
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
  if (local == 0u) {
    const int at = reachEntry(tileCount());
    for (int d = 0; d < 3; ++d) {
      reach[at + d] = highest[0][d];
      reach[at + 4 + d] = lowest[0][d];
    }
  }
}
