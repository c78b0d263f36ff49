#version 450
#extension GL_GOOGLE_include_directive : require
// Stencil masks of one grid level from its flags (bit layout in obstacle_flags.glsl), in the padded
// layout of the solver (width ≥ nx, multigrid_blocks.glsl; padding cells get mask 0):
//   mask_c = fluid(c) + 2·open(c) + Σ_n 4·2^n·open(c + step_n) + Σ_n 256·2^n·fluid(c + step_n),
// open = not an obstacle, neighbours outside the grid are obstacles. One invocation per padded cell.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(std430, binding = 1) writeonly buffer Masks { float masks[]; };
layout(push_constant) uniform Push { ivec3 size; int width; };

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, ivec3(width, size.yz))) return;
  if (c.x >= size.x) {
    masks[padded_index(c, size, width)] = 0.0;
    return;
  }
  const uint flag = cell_flag(flags, c, size);
  uint mask = (is_fluid(flag) ? MASK_FLUID : 0u) | (is_obstacle(flag) ? 0u : MASK_OPEN);
  for (int n = 0; n < 6; ++n) {
    const uint neighbour = cell_flag(flags, c + neighbour_step(n), size);
    if (!is_obstacle(neighbour)) mask |= 4u << n;
    if (is_fluid(neighbour)) mask |= 256u << n;
  }
  masks[padded_index(c, size, width)] = float(mask);
}
