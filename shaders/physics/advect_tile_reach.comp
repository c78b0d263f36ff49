#version 450
#extension GL_GOOGLE_include_directive : require
// The reach of each tile of one plane, one invocation per tile U (advect_tiles.glsl has the layout):
//   reach[U][d] = REACH_BIAS + max over interior c in U of o_d(c), reach[U][4 + d] the same of −o_d,
// with o(c) = b(c) − c the offset of the stored departure stencil's base (0: no interior cell).
#include "advect_sampling.glsl"
#include "advect_tiles.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer departure;  // vec4 texels
layout(std430, binding = 1) writeonly buffer Reach { int reach[]; };

void main() {
  const ivec3 tile = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(tile, tileGrid()))) return;
  const ivec3 first = tile * TILE;
  const ivec3 last = min(first + TILE - 1, n - 1);
  ivec3 high = ivec3(-REACH_BIAS);
  ivec3 low = ivec3(-REACH_BIAS);
  for (int z = first.z; z <= last.z; ++z) {
    for (int j = first.y; j <= last.y; ++j) {
      for (int i = first.x; i <= last.x; ++i) {
        const ivec3 c = ivec3(i, j, z);
        const vec4 stored = texelFetch(departure, plane * cellCount() + cellIndex(c));
        if (stored.w < 0.0) continue;
        const ivec3 offset = min(ivec3(stored.xyz), n - 2) - c;
        high = max(high, offset);
        low = max(low, -offset);
      }
    }
  }
  const int at = reachEntry(tileIndex(tile));
  const bool reached = high.x > -REACH_BIAS;
  for (int d = 0; d < 3; ++d) {
    reach[at + d] = reached ? REACH_BIAS + high[d] : 0;
    reach[at + 4 + d] = reached ? REACH_BIAS + low[d] : 0;
  }
}
