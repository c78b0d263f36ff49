#version 450
#extension GL_GOOGLE_include_directive : require
// Which blocks of a volume are occupied (occupied_box.glsl), the first pass of its occupied box:
//   occupied[k] = 1 if v[u] != 0 for some voxel u of the block, [B k, B (k + 1) - 1] (each axis, inside the grid), else 0
// B = OCCUPIED_BLOCK; k a block of the grid ceil(size / B). One invocation per block.
#include "index.glsl"
#include "occupied_box.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer volume;
layout(std430, binding = 1) writeonly buffer Occupied { float occupied[]; };
layout(push_constant) uniform Push {
  int width, height, depth;
  int blocksX, blocksY, blocksZ;
};

void main() {
  const uint item = flat_index();
  const ivec3 blocks = ivec3(blocksX, blocksY, blocksZ);
  if (item >= uint(blocks.x * blocks.y * blocks.z)) return;
  const ivec3 block = ivec3(int(item) % blocks.x, (int(item) / blocks.x) % blocks.y, int(item) / (blocks.x * blocks.y));
  const ivec3 size = ivec3(width, height, depth);
  const ivec3 first = OCCUPIED_BLOCK * block, last = min(OCCUPIED_BLOCK * (block + 1), size) - 1;
  bool nonzero = false;
  for (int z = first.z; z <= last.z; ++z)
    for (int y = first.y; y <= last.y; ++y)
      for (int x = first.x; x <= last.x; ++x) nonzero = nonzero || texelFetch(volume, (z * size.y + y) * size.x + x).x != 0.0;
  occupied[item] = nonzero ? 1.0 : 0.0;
}
