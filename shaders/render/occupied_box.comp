#version 450
#extension GL_GOOGLE_include_directive : require
// The occupied box of a volume from which of its blocks are occupied (block_occupancy.comp, occupied_box.glsl):
//   box[0].xyz = low = B min k - 1/2,  box[1].xyz = high = B (max k + 1) + 1/2   over the occupied blocks k,
// or low = 1e30, high = -1e30 where none is. One workgroup of G invocations (G a power of two), each taking
// every G-th block, then a tree in shared memory.
#include "occupied_box.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer occupied;
layout(std430, binding = 1) writeonly buffer Box { vec4 box[2]; };
layout(push_constant) uniform Push {
  int blocksX, blocksY, blocksZ;
};

shared ivec3 lowest[gl_WorkGroupSize.x];
shared ivec3 highest[gl_WorkGroupSize.x];

void main() {
  const uint local = gl_LocalInvocationID.x;
  const ivec3 blocks = ivec3(blocksX, blocksY, blocksZ);
  ivec3 low = blocks, high = ivec3(-1);
  for (int k = int(local); k < blocks.x * blocks.y * blocks.z; k += int(gl_WorkGroupSize.x)) {
    if (texelFetch(occupied, k).x == 0.0) continue;
    const ivec3 block = ivec3(k % blocks.x, (k / blocks.x) % blocks.y, k / (blocks.x * blocks.y));
    low = min(low, block);
    high = max(high, block);
  }
  lowest[local] = low;
  highest[local] = high;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) {
      lowest[local] = min(lowest[local], lowest[local + half_]);
      highest[local] = max(highest[local], highest[local + half_]);
    }
    barrier();
  }
  if (local == 0u) {
    const bool none = highest[0].x < 0;
    box[0] = none ? vec4(1.0e30) : vec4(vec3(OCCUPIED_BLOCK * lowest[0]) - 0.5, 0.0);
    box[1] = none ? vec4(-1.0e30) : vec4(vec3(OCCUPIED_BLOCK * (highest[0] + 1)) + 0.5, 0.0);
  }
}
