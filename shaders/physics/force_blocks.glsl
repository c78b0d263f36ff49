// Blocks of four cells along x for the kernels that work in the user's layout ([..., nz, ny, nx] with nx a
// multiple of 4, fields bound as vec4 texels): the force, vorticity and projection-boundary kernels'
// block variants. Block b = (g, j, k) covers cells 4g … 4g+3 of row (j, k); `blocks` = (nx/4, ny, nz);
// plane p of a vector field starts at texel p·plane_texels(blocks). Include after obstacle_flags.glsl and
// multigrid_blocks.glsl.
#ifndef SMOKESVD_FORCE_BLOCKS_GLSL
#define SMOKESVD_FORCE_BLOCKS_GLSL

int plane_texels(ivec3 blocks) { return blocks.x * blocks.y * blocks.z; }

// The value of each lane's lower neighbour along x, y and z (`outside` past the grid).
struct Lower {
  vec4 x, y, z;
};

Lower lower_neighbours(samplerBuffer v, int t, vec4 centre, ivec3 b, ivec3 blocks, float outside) {
  Lower l;
  l.x = vec4(b.x > 0 ? texelFetch(v, t - 1).w : outside, centre.xyz);
  l.y = b.y > 0 ? texelFetch(v, t - blocks.x) : vec4(outside);
  l.z = b.z > 0 ? texelFetch(v, t - blocks.x * blocks.y) : vec4(outside);
  return l;
}

vec4 obstacle_lanes(vec4 flags) { return vec4((uvec4(flags) & uvec4(FLAG_OBSTACLE)) >> 1u); }
vec4 fluid_flag_lanes(vec4 flags) { return vec4(uvec4(flags) & uvec4(FLAG_FLUID)); }
// 1 where the face between cells with flags c and m takes a force (force_faces.glsl), else 0.
vec4 force_acts4(vec4 c, vec4 m) {
  return (1.0 - obstacle_lanes(c)) * (1.0 - obstacle_lanes(m)) * min(fluid_flag_lanes(c) + fluid_flag_lanes(m), 1.0);
}

// 1 for lanes whose cell is interior (not on the outer layer), else 0.
vec4 interior_lanes(ivec3 b, ivec3 blocks) {
  const ivec3 size = ivec3(4 * blocks.x, blocks.yz);
  if (b.y == 0 || b.z == 0 || b.y == size.y - 1 || b.z == size.z - 1) return vec4(0.0);
  const ivec4 x = 4 * b.x + ivec4(0, 1, 2, 3);
  return vec4(greaterThan(x, ivec4(0))) * vec4(lessThan(x, ivec4(size.x - 1)));
}

#endif
