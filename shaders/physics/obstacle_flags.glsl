// Cells of the simulation grid and their flags, shared by the pressure, multigrid, force and inflow
// kernels. Flags are mantaflow's bits stored as floats: 1 fluid, 2 obstacle, 4 empty (open, p = 0).
//
// Index names: size = grid size (nx, ny, nz) in cells; c = integer cell (i, j, k), centred at c + ½,
// flat index i + nx·(j + ny·k); e_a = unit step along axis a. A vector field is planar [3, nz, ny, nx]:
// plane a at offset a·cells, for a MAC field the value at the lower a-face of c. Cells outside the
// grid count as obstacle, so stencils need no special case at the border.
#ifndef SMOKESVD_OBSTACLE_FLAGS_GLSL
#define SMOKESVD_OBSTACLE_FLAGS_GLSL

const uint FLAG_FLUID = 1u;
const uint FLAG_OBSTACLE = 2u;
const uint FLAG_EMPTY = 4u;

int cell_count(ivec3 size) { return size.x * size.y * size.z; }
int cell_index(ivec3 c, ivec3 size) { return c.x + size.x * (c.y + size.y * c.z); }
ivec3 cell_of(int index, ivec3 size) {
  return ivec3(index % size.x, (index / size.x) % size.y, index / (size.x * size.y));
}
bool in_grid(ivec3 c, ivec3 size) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, size)); }
ivec3 unit_step(int axis) { return ivec3(axis == 0 ? 1 : 0, axis == 1 ? 1 : 0, axis == 2 ? 1 : 0); }

uint cell_flag(samplerBuffer flags, ivec3 c, ivec3 size) {
  return in_grid(c, size) ? uint(texelFetch(flags, cell_index(c, size)).x) : FLAG_OBSTACLE;
}
bool is_fluid(uint flag) { return (flag & FLAG_FLUID) != 0u; }
bool is_obstacle(uint flag) { return (flag & FLAG_OBSTACLE) != 0u; }

#endif
