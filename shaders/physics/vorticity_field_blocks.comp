#version 450
#extension GL_GOOGLE_include_directive : require
// vorticity_field.comp for grids whose width is a multiple of 4, four cells per invocation
// (force_blocks.glsl): centred velocity v_d(n) = ½(u_d(n) + u_d(n + e_d)) at interior cells (0 on the outer
// layer), ω = ∇ × v by central differences at interior cells (0 on the outer layer); output planes
// [4, nz, ny, nx] = ω_x, ω_y, ω_z, |ω|. A row (j, k) of v_d costs two texel fetches; the ±x neighbours of
// the block's end lanes two more each.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Vorticity { vec4 vorticity[]; };
layout(push_constant) uniform Push { ivec3 blocks; };

int plane;

int texel(int component, int g, int j, int k) { return component * plane + g + blocks.x * (j + blocks.y * k); }

// 1 for the lanes of block (g, j, k) that are interior cells.
vec4 interior_row(int g, int j, int k) { return interior_lanes(ivec3(g, j, k), blocks); }

// v_component over the four cells of block (g, j, k).
vec4 centred_row(int component, int g, int j, int k) {
  const vec4 inside = interior_row(g, j, k);
  if (!any(greaterThan(inside, vec4(0.0)))) return vec4(0.0);
  const vec4 u = texelFetch(velocity, texel(component, g, j, k));
  vec4 next;
  if (component == 0) next = vec4(u.yzw, texelFetch(velocity, texel(0, g + 1, j, k)).x);
  else if (component == 1) next = texelFetch(velocity, texel(1, g, j + 1, k));
  else next = texelFetch(velocity, texel(2, g, j, k + 1));
  return inside * 0.5 * (u + next);
}

// v_component at the cell before (side −1) or after (side +1) the block in its row, 0 past the grid.
float centred_beside(int component, int g, int j, int k, int side) {
  const int x = side < 0 ? 4 * g - 1 : 4 * g + 4;
  if (x <= 0 || x >= 4 * blocks.x - 1) return 0.0;
  const int gb = g + side;
  const int lane = side < 0 ? 3 : 0;
  const float u = texelFetch(velocity, texel(component, gb, j, k))[lane];
  float next;
  if (component == 1) next = texelFetch(velocity, texel(1, gb, j + 1, k))[lane];
  else next = texelFetch(velocity, texel(2, gb, j, k + 1))[lane];
  return 0.5 * (u + next);
}

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  plane = plane_texels(blocks);
  const int t = block_index(b, blocks);
  const vec4 inside = interior_lanes(b, blocks);
  vec4 wx = vec4(0.0), wy = vec4(0.0), wz = vec4(0.0);
  if (any(greaterThan(inside, vec4(0.0)))) {
    const int g = b.x, j = b.y, k = b.z;
    const vec4 zy = centred_row(2, g, j + 1, k) - centred_row(2, g, j - 1, k);
    const vec4 yz = centred_row(1, g, j, k + 1) - centred_row(1, g, j, k - 1);
    const vec4 xz = centred_row(0, g, j, k + 1) - centred_row(0, g, j, k - 1);
    const vec4 xy = centred_row(0, g, j + 1, k) - centred_row(0, g, j - 1, k);
    const vec4 z = centred_row(2, g, j, k), y = centred_row(1, g, j, k);
    const vec4 zx = vec4(z.yzw, centred_beside(2, g, j, k, 1)) - vec4(centred_beside(2, g, j, k, -1), z.xyz);
    const vec4 yx = vec4(y.yzw, centred_beside(1, g, j, k, 1)) - vec4(centred_beside(1, g, j, k, -1), y.xyz);
    wx = inside * 0.5 * (zy - yz);
    wy = inside * 0.5 * (xz - zx);
    wz = inside * 0.5 * (yx - xy);
  }
  vorticity[t] = wx;
  vorticity[plane + t] = wy;
  vorticity[2 * plane + t] = wz;
  vorticity[3 * plane + t] = sqrt(wx * wx + wy * wy + wz * wz);
}
