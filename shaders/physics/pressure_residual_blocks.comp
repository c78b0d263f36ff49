#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// pressure_residual.comp for grids whose width is a multiple of 4 (the padded layout is then the user's),
// four cells per invocation (multigrid_blocks.glsl):
//   b_c = −Σ_a (open(c + e_a)·u_a(c + e_a) − open(c − e_a)·u_a(c)),   residual_c = b_c − (d_c·p_c − Σ_n p_n)
// at fluid cells, 0 elsewhere (p0 is 0 outside the fluid); partial sets as in pressure_residual.comp:
// max |b|, max |residual|, Σ residual per subgroup.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
#include "pressure_partials.glsl"

layout(binding = 0) uniform samplerBuffer masks;
layout(binding = 1) uniform samplerBuffer velocity;
layout(binding = 2) uniform samplerBuffer pressure;
layout(std430, binding = 3) writeonly buffer Residual { vec4 residual[]; };
layout(std430, binding = 4) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { ivec3 blocks; uint count; };

// 1 for lanes whose neighbour n is not an obstacle.
vec4 open_lanes(uvec4 m, int n) { return vec4((m >> uint(2 + n)) & uvec4(1u)); }

void main() {
  const ivec3 b = dispatch_block();
  vec4 bb = vec4(0.0), r = vec4(0.0);
  if (block_in_grid(b, blocks)) {
    const int t = block_index(b, blocks);
    const int plane = plane_texels(blocks);
    const uvec4 m = block_masks(masks, t);
    const vec4 ux = texelFetch(velocity, t);
    const vec4 uxNext = vec4(ux.yzw, b.x < blocks.x - 1 ? texelFetch(velocity, t + 1).x : 0.0);
    const vec4 uy = texelFetch(velocity, plane + t);
    const vec4 uyNext = b.y < blocks.y - 1 ? texelFetch(velocity, plane + t + blocks.x) : vec4(0.0);
    const vec4 uz = texelFetch(velocity, 2 * plane + t);
    const vec4 uzNext = b.z < blocks.z - 1 ? texelFetch(velocity, 2 * plane + t + blocks.x * blocks.y) : vec4(0.0);
    const vec4 divergence = (open_lanes(m, 1) * uxNext - open_lanes(m, 0) * ux) +
                            (open_lanes(m, 3) * uyNext - open_lanes(m, 2) * uy) +
                            (open_lanes(m, 5) * uzNext - open_lanes(m, 4) * uz);
    const vec4 pc = texelFetch(pressure, t);
    const vec4 laplacian = open_neighbours(m) * pc - neighbour_sum(neighbours(pressure, pc, b, blocks));
    const vec4 fluid = fluid_lanes(m);
    bb = -fluid * divergence;
    r = fluid * (-divergence - laplacian);
    residual[t] = r;
  }
  const vec4 ab = abs(bb), ar = abs(r);
  STORE_PARTIAL_MAX(partial, 0u, max(max(ab.x, ab.y), max(ab.z, ab.w)));
  STORE_PARTIAL_MAX(partial, count, max(max(ar.x, ar.y), max(ar.z, ar.w)));
  STORE_PARTIAL_SUM(partial, 2u * count, r.x + r.y + r.z + r.w);
}
