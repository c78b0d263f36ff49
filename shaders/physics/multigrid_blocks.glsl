// Blocks of four cells along x, the unit of work of the solver's inner kernels: invocation (g, j, k) of
// a 3D dispatch handles cells 4g … 4g+3 of row (j, k) and reads each field as vec4 texels (one fetch
// for four cells, the fast path on CPU devices). The solver keeps its vectors in a padded layout:
// [nz, ny, P] with P = nx rounded up to a multiple of 4, blocks = (P/4, ny, nz); padding cells have
// mask 0 and value 0.
//
// Every vector of the solver is 0 outside the fluid (kernels write 0 there), so the stencil needs no
// neighbour flags: (A x)_c = d_c·x_c − Σ_n x_n, d_c = number of non-obstacle neighbours (empty
// neighbours are Dirichlet, x = 0; obstacles drop out of d). Include after obstacle_flags.glsl.
#ifndef SMOKESVD_MULTIGRID_BLOCKS_GLSL
#define SMOKESVD_MULTIGRID_BLOCKS_GLSL

ivec3 dispatch_block() { return ivec3(gl_GlobalInvocationID); }
bool block_in_grid(ivec3 b, ivec3 blocks) { return all(lessThan(b, blocks)); }
int block_index(ivec3 b, ivec3 blocks) { return b.x + blocks.x * (b.y + blocks.y * b.z); }

// The six neighbours' values of a block's four cells.
struct Neighbours {
  vec4 left, right, down, up, back, front;
};

// The six neighbours' values of the block at texel t (of any plane: t may be offset by whole planes),
// 0 outside the padded grid.
Neighbours neighbours_at(samplerBuffer v, int t, vec4 centre, ivec3 b, ivec3 blocks) {
  const int row = blocks.x, slice = blocks.x * blocks.y;
  Neighbours n;
  n.left = vec4(b.x > 0 ? texelFetch(v, t - 1).w : 0.0, centre.xyz);
  n.right = vec4(centre.yzw, b.x < blocks.x - 1 ? texelFetch(v, t + 1).x : 0.0);
  n.down = b.y > 0 ? texelFetch(v, t - row) : vec4(0.0);
  n.up = b.y < blocks.y - 1 ? texelFetch(v, t + row) : vec4(0.0);
  n.back = b.z > 0 ? texelFetch(v, t - slice) : vec4(0.0);
  n.front = b.z < blocks.z - 1 ? texelFetch(v, t + slice) : vec4(0.0);
  return n;
}

// The same for the block's own texel of a one-plane field.
Neighbours neighbours(samplerBuffer v, vec4 centre, ivec3 b, ivec3 blocks) {
  return neighbours_at(v, block_index(b, blocks), centre, b, blocks);
}

vec4 neighbour_sum(Neighbours n) { return (n.left + n.right) + (n.down + n.up) + (n.back + n.front); }

uvec4 block_masks(samplerBuffer masks, int t) { return uvec4(texelFetch(masks, t)); }
vec4 fluid_lanes(uvec4 m) { return vec4(m & uvec4(MASK_FLUID)); }
// d_c: non-obstacle neighbours per lane.
vec4 open_neighbours(uvec4 m) { return vec4(bitCount((m >> 2u) & uvec4(63u))); }

#endif
