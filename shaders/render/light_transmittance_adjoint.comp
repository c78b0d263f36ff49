#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of light_transmittance.comp, as a gather. With H(v) = -absorption * step * T_L(v) * gT(v)
// (gT = dL/dT_L), the density gradient is
//   g_sigma(q) = direct(q) + sum_{j >= 0} H~(c_q - (j + 1/2) * step * l)
// where H~ is H sampled trilinearly with zero padding: the forward sample of voxel v at c_v + s_j gives q the
// weight tent(c_v + s_j - c_q), which is the trilinear weight of v at c_q - s_j. The march away from the light
// stops where it leaves the box [-1/2, N + 1/2]. direct(q) is the gradient that reached sigma by other paths.
// A sample whose stencil's gT is zero at every corner adds exactly 0, so the march takes only the samples that
// can fall inside gT's occupied box (occupied_box.glsl): the same sum bit for bit.
#include "index.glsl"
#include "sampling.glsl"
#include "look.glsl"
#include "occupied_box.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer transmittance_quads;       // corner quads (corner_quads.comp) of T_L
layout(binding = 1) uniform samplerBuffer grad_transmittance_quads;  // and of gT
layout(binding = 2) uniform samplerBuffer direct;
layout(std430, binding = 3) writeonly buffer GradDensity { float grad_density[]; };
layout(binding = 4) uniform samplerBuffer look;
layout(binding = 5) uniform samplerBuffer box;  // gT's occupied box: low, high (occupied_box.comp)
layout(push_constant) uniform Push {
  int width, height, depth;
  float step_length;
};

// H~(p) / (-absorption * step): the corners' T_L * gT, trilinear, read as corner quads (two texels of each
// instead of eight scalars; a corner outside the volume is 0 there, adding nothing).
float sample_h(ivec3 size, vec3 p) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  const int i = quad_index(base, size), above = (size.x + 1) * (size.y + 1);
  const vec4 t[2] = vec4[2](texelFetch(transmittance_quads, i), texelFetch(transmittance_quads, i + above));
  const vec4 g[2] = vec4[2](texelFetch(grad_transmittance_quads, i), texelFetch(grad_transmittance_quads, i + above));
  float value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    value += corner_weight(offset, f) * t[offset.z][corner & 3] * g[offset.z][corner & 3];
  }
  return value;
}

void main() {
  const uint item = flat_index();
  const ivec3 size = ivec3(width, height, depth);
  if (item >= uint(width * height * depth)) return;
  const int x = int(item) % width, y = (int(item) / width) % height, z = int(item) / (width * height);
  const vec3 away = -step_length * look_light_direction(look);
  const float absorption = look_light_absorption(look);
  const vec3 lo = vec3(-0.5), hi = vec3(size) + 0.5;
  const vec3 centre = vec3(x, y, z) + 0.5;
  const vec2 range = samples_in_box(centre, away, texelFetch(box, 0).xyz, texelFetch(box, 1).xyz);
  float sum = 0.0;
  for (float j = first_sample_in(range); j <= range.y; j += 1.0) {
    const vec3 p = centre + j * away;
    if (any(lessThanEqual(p, lo)) || any(greaterThanEqual(p, hi))) break;
    sum += sample_h(size, p);
  }
  grad_density[item] = texelFetch(direct, int(item)).x - absorption * step_length * sum;
}
