// Cells of the simulation grid, their flags and stencil masks, shared by the pressure, multigrid,
// force and inflow kernels. Flags are mantaflow's bits stored as floats: 1 fluid, 2 obstacle,
// 4 empty (open, p = 0).
//
// Index names: size = grid size (nx, ny, nz) in cells; c = integer cell (i, j, k), centred at c + ½,
// flat index i + nx·(j + ny·k); e_a = unit step along axis a. A vector field is planar [3, nz, ny, nx]:
// plane a at offset a·cells, for a MAC field the value at the lower a-face of c. Cells outside the
// grid count as obstacle. Grid kernels run one invocation per cell on a 3D dispatch (dispatch_cell();
// no integer division, which is slow on CPU devices).
//
// A stencil mask (pressure_stencil.comp) packs what a 7-point stencil needs to know into one float:
// bit 0 the cell is fluid, bit 1 it is not an obstacle, bit 2 + n neighbour n is not an obstacle,
// bit 8 + n neighbour n is fluid, for the neighbours n = 0..5 = −x, +x, −y, +y, −z, +z.
#ifndef SMOKESVD_OBSTACLE_FLAGS_GLSL
#define SMOKESVD_OBSTACLE_FLAGS_GLSL

const uint FLAG_FLUID = 1u;
const uint FLAG_OBSTACLE = 2u;
const uint FLAG_EMPTY = 4u;

int cell_count(ivec3 size) { return size.x * size.y * size.z; }
int cell_index(ivec3 c, ivec3 size) { return c.x + size.x * (c.y + size.y * c.z); }
// The index of cell c in a padded volume [nz, ny, width] (width ≥ nx; multigrid_blocks.glsl).
int padded_index(ivec3 c, ivec3 size, int width) { return c.x + width * (c.y + size.y * c.z); }
ivec3 dispatch_cell() { return ivec3(gl_GlobalInvocationID); }
bool in_grid(ivec3 c, ivec3 size) { return all(greaterThanEqual(c, ivec3(0))) && all(lessThan(c, size)); }
ivec3 unit_step(int axis) { return ivec3(axis == 0 ? 1 : 0, axis == 1 ? 1 : 0, axis == 2 ? 1 : 0); }

uint cell_flag(samplerBuffer flags, ivec3 c, ivec3 size) {
  return in_grid(c, size) ? uint(texelFetch(flags, cell_index(c, size)).x) : FLAG_OBSTACLE;
}
bool is_fluid(uint flag) { return (flag & FLAG_FLUID) != 0u; }
bool is_obstacle(uint flag) { return (flag & FLAG_OBSTACLE) != 0u; }

const uint MASK_FLUID = 1u;
const uint MASK_OPEN = 2u;
uint stencil_mask(samplerBuffer masks, int index) { return uint(texelFetch(masks, index).x); }
bool mask_fluid(uint mask) { return (mask & MASK_FLUID) != 0u; }
bool mask_open(uint mask) { return (mask & MASK_OPEN) != 0u; }
bool neighbour_open(uint mask, int n) { return (mask & (4u << n)) != 0u; }
bool neighbour_fluid(uint mask, int n) { return (mask & (256u << n)) != 0u; }
// Neighbour n of a cell: its step and the offset of its flat index.
ivec3 neighbour_step(int n) { return ((n & 1) == 0 ? -1 : 1) * unit_step(n >> 1); }
int neighbour_offset(int n, ivec3 size) {
  const int stride = n < 2 ? 1 : (n < 4 ? size.x : size.x * size.y);
  return (n & 1) == 0 ? -stride : stride;
}

#endif
