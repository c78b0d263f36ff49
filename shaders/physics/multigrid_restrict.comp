#version 450
#extension GL_GOOGLE_include_directive : require
// Residual of a fine level restricted to the next coarser one (sum over the 2×2×2 children):
//   coarseRhs_C = γ · Σ over fluid children f of C of (rhs_f − (A x)_f)   at fluid coarse cells C, else 0,
//   (A x)_f = Σ over non-obstacle neighbours n of (x_f − x_n),  x_n = 0 unless n is fluid.
// Children of C are f = 2C + (0|1, 0|1, 0|1) inside the fine grid. γ scales the coarse right-hand side
// (½ for a coarse operator with the fine stencil's integer weights: the 2h Laplacian is ¼ of it and
// the rhs an average of 8). Index names and stencil masks in obstacle_flags.glsl; size is the fine size.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer rhs;
layout(binding = 2) uniform samplerBuffer x;
layout(binding = 3) uniform samplerBuffer coarseMasks;
layout(std430, binding = 4) writeonly buffer CoarseRhs { float coarseRhs[]; };
layout(push_constant) uniform Push { ivec3 size; float gamma; ivec3 coarseSize; };

float residualAt(int index, uint mask) {
  const float xf = texelFetch(x, index).x;
  float ax = 0.0;
  for (int n = 0; n < 6; ++n) {
    if (!neighbour_open(mask, n)) continue;
    ax += xf - (neighbour_fluid(mask, n) ? texelFetch(x, index + neighbour_offset(n, size)).x : 0.0);
  }
  return texelFetch(rhs, index).x - ax;
}

void main() {
  const ivec3 coarseCell = dispatch_cell();
  if (!in_grid(coarseCell, coarseSize)) return;
  const int coarseIndex = cell_index(coarseCell, coarseSize);
  float sum = 0.0;
  if (mask_fluid(stencil_mask(coarseMasks, coarseIndex))) {
    for (int child = 0; child < 8; ++child) {
      const ivec3 f = 2 * coarseCell + ivec3(child & 1, (child >> 1) & 1, child >> 2);
      if (!in_grid(f, size)) continue;
      const int index = cell_index(f, size);
      const uint mask = stencil_mask(masks, index);
      if (mask_fluid(mask)) sum += residualAt(index, mask);
    }
  }
  coarseRhs[coarseIndex] = gamma * sum;
}
