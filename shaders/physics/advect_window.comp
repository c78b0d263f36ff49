#version 450
#extension GL_GOOGLE_include_directive : require
// Gather windows of the advection adjoint, one invocation per source tile T of one plane. A target
// tile U (reach from advect_tile_reach) hands weight to the cells [U_min + min o, U_max + max o + 1] per
// axis; window(T) is the union of the offset ranges [min o, max o] of every target tile whose range
// meets T, searched within the plane's overall reach. Written as window[8·(plane·tiles + T)]:
// [0..2] REACH_BIAS + max o_d, [4..6] REACH_BIAS + max −o_d (0: no target reaches T).
// A source cell y then gathers from targets x_d ∈ [y_d − 1 − max o_d, y_d + max −o_d].
#include "advect_sampling.glsl"
#include "advect_tiles.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(std430, binding = 0) readonly buffer Reach { int reach[]; };
layout(std430, binding = 1) writeonly buffer Window { int window[]; };

ivec3 reachHigh(int entry) { return ivec3(reach[entry], reach[entry + 1], reach[entry + 2]) - REACH_BIAS; }
ivec3 reachLow(int entry) { return ivec3(reach[entry + 4], reach[entry + 5], reach[entry + 6]) - REACH_BIAS; }

void main() {
  const ivec3 tile = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(tile, tileGrid()))) return;
  const ivec3 sourceFirst = tile * TILE;
  const ivec3 sourceLast = min(sourceFirst + TILE - 1, n - 1);
  ivec3 high = ivec3(-REACH_BIAS);
  ivec3 low = ivec3(-REACH_BIAS);
  const int whole = reachEntry(tileCount());
  if (reach[whole] != 0) {
    const ivec3 radius = (max(reachHigh(whole), reachLow(whole)) + 1 + TILE - 1) / TILE;
    const ivec3 first = max(tile - radius, ivec3(0));
    const ivec3 last = min(tile + radius, tileGrid() - 1);
    for (int z = first.z; z <= last.z; ++z) {
      for (int j = first.y; j <= last.y; ++j) {
        for (int i = first.x; i <= last.x; ++i) {
          const ivec3 target = ivec3(i, j, z);
          const int entry = reachEntry(tileIndex(target));
          if (reach[entry] == 0) continue;
          const ivec3 targetFirst = target * TILE;
          const ivec3 targetLast = min(targetFirst + TILE - 1, n - 1);
          const ivec3 touchedFirst = targetFirst - reachLow(entry);
          const ivec3 touchedLast = targetLast + reachHigh(entry) + 1;
          if (any(greaterThan(touchedFirst, sourceLast)) || any(lessThan(touchedLast, sourceFirst))) continue;
          high = max(high, reachHigh(entry));
          low = max(low, reachLow(entry));
        }
      }
    }
  }
  const int at = 8 * (plane * tileCount() + tileIndex(tile));
  const bool reached = high.x > -REACH_BIAS;
  for (int d = 0; d < 3; ++d) {
    window[at + d] = reached ? REACH_BIAS + high[d] : 0;
    window[at + 4 + d] = reached ? REACH_BIAS + low[d] : 0;
  }
}
