#version 450
#extension GL_GOOGLE_include_directive : require
// force_field.comp for grids whose width is a multiple of 4, four cells per invocation
// (force_blocks.glsl): on every face that takes a force, the lower a-face of c with m = c − e_a,
//   u_a(c) += dt·½(f_a(c) + f_a(m)),
// f a cell-centred acceleration field [3, nz, ny, nx]; other faces copied.
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer force;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push { ivec3 blocks; float dt; };

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const int plane = plane_texels(blocks);
  const vec4 flagC = texelFetch(flags, t);
  const Lower flagM = lower_neighbours(flags, t, flagC, b, blocks, float(FLAG_OBSTACLE));
  const vec4 fx = texelFetch(force, t), fy = texelFetch(force, plane + t), fz = texelFetch(force, 2 * plane + t);
  const vec4 fxm = lower_neighbours(force, t, fx, b, blocks, 0.0).x;
  const vec4 fym = lower_neighbours(force, plane + t, fy, b, blocks, 0.0).y;
  const vec4 fzm = lower_neighbours(force, 2 * plane + t, fz, b, blocks, 0.0).z;
  result[t] = texelFetch(velocity, t) + dt * 0.5 * force_acts4(flagC, flagM.x) * (fx + fxm);
  result[plane + t] = texelFetch(velocity, plane + t) + dt * 0.5 * force_acts4(flagC, flagM.y) * (fy + fym);
  result[2 * plane + t] = texelFetch(velocity, 2 * plane + t) + dt * 0.5 * force_acts4(flagC, flagM.z) * (fz + fzm);
}
