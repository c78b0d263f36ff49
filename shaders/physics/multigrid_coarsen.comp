#version 450
#extension GL_GOOGLE_include_directive : require
// Flags of the next coarser multigrid level from its 2×2×2 children f = 2C + (0|1, 0|1, 0|1):
//   coarse_C = empty    if any child inside the fine grid is empty (open boundaries win),
//              fluid    else if any child is fluid,
//              obstacle otherwise.
// Index names in obstacle_flags.glsl; size is the fine size.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(std430, binding = 1) writeonly buffer CoarseFlags { float coarseFlags[]; };
layout(push_constant) uniform Push { ivec3 size; int unused; ivec3 coarseSize; };

void main() {
  const ivec3 coarseCell = dispatch_cell();
  if (!in_grid(coarseCell, coarseSize)) return;
  bool anyEmpty = false;
  bool anyFluid = false;
  for (int child = 0; child < 8; ++child) {
    const ivec3 f = 2 * coarseCell + ivec3(child & 1, (child >> 1) & 1, child >> 2);
    if (!in_grid(f, size)) continue;
    const uint flag = cell_flag(flags, f, size);
    anyEmpty = anyEmpty || (!is_obstacle(flag) && !is_fluid(flag));
    anyFluid = anyFluid || is_fluid(flag);
  }
  coarseFlags[cell_index(coarseCell, coarseSize)] =
      anyEmpty ? float(FLAG_EMPTY) : (anyFluid ? float(FLAG_FLUID) : float(FLAG_OBSTACLE));
}
