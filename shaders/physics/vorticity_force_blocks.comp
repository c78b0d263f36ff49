#version 450
#extension GL_GOOGLE_include_directive : require
// vorticity_force.comp for grids whose width is a multiple of 4, four cells per invocation
// (force_blocks.glsl): with the vorticity planes [4, nz, ny, nx] = ω_x, ω_y, ω_z, |ω|,
//   N = normalise(½(|ω|(c + e_a) − |ω|(c − e_a)))_a (0 where the gradient vanishes),
//   F(c) = ε·N × ω(c) at interior cells, 0 on the outer layer; output planar [3, nz, ny, nx].
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer vorticity;
layout(std430, binding = 1) writeonly buffer Force { vec4 force[]; };
layout(push_constant) uniform Push { ivec3 blocks; float strength; };

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const int plane = plane_texels(blocks);
  const vec4 inside = interior_lanes(b, blocks);
  vec4 fx = vec4(0.0), fy = vec4(0.0), fz = vec4(0.0);
  if (any(greaterThan(inside, vec4(0.0)))) {
    const int magnitude = 3 * plane + t;
    const Neighbours m = neighbours_at(vorticity, magnitude, texelFetch(vorticity, magnitude), b, blocks);
    const vec4 gx = 0.5 * (m.right - m.left), gy = 0.5 * (m.up - m.down), gz = 0.5 * (m.front - m.back);
    const vec4 norm = sqrt(gx * gx + gy * gy + gz * gz);
    const vec4 scale = inside * strength * mix(1.0 / max(norm, vec4(1e-30)), vec4(0.0), lessThanEqual(norm, vec4(1e-20)));
    const vec4 wx = texelFetch(vorticity, t), wy = texelFetch(vorticity, plane + t), wz = texelFetch(vorticity, 2 * plane + t);
    fx = scale * (gy * wz - gz * wy);
    fy = scale * (gz * wx - gx * wz);
    fz = scale * (gx * wy - gy * wx);
  }
  force[t] = fx;
  force[plane + t] = fy;
  force[2 * plane + t] = fz;
}
