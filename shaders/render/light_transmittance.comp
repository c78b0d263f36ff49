#version 450
#extension GL_GOOGLE_include_directive : require
// Light transmittance of a directional light at every voxel centre (the shadow pass):
//   T_L(v) = exp(-absorption * step * sum_{j >= 0} sigma(c_v + (j + 1/2) * step * l))
// v = (x, y, z) voxel, c_v its centre, l the unit direction toward the light (grid coordinates), sigma the
// density sampled trilinearly with zero padding. Samples stop where they leave the box [-1/2, N + 1/2],
// beyond which sigma is 0. l and the absorption come from the look buffer (look.glsl). One invocation per voxel; a gather, so the adjoint is a gather too
// (light_transmittance_adjoint.comp). The lookups read the density's corner quads (corner_quads.comp): two
// texels a sample where the stencil lies inside the grid instead of eight. Samples outside the density's occupied
// box (occupied_box.glsl) add exactly 0, so the march takes only those that can lie inside it: the same sum bit
// for bit.
#include "index.glsl"
#include "sampling.glsl"
#include "look.glsl"
#include "occupied_box.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer density;
layout(std430, binding = 1) writeonly buffer Transmittance { float transmittance[]; };
layout(binding = 2) uniform samplerBuffer look;
layout(binding = 3) uniform samplerBuffer quads;  // the density's corner quads
layout(binding = 4) uniform samplerBuffer box;    // the density's occupied box: low, high (occupied_box.comp)
layout(push_constant) uniform Push {
  int width, height, depth;
  float step_length;
};

void main() {
  const uint item = flat_index();
  const ivec3 size = ivec3(width, height, depth);
  if (item >= uint(width * height * depth)) return;
  const int x = int(item) % width, y = (int(item) / width) % height, z = int(item) / (width * height);
  const vec3 toward = step_length * look_light_direction(look);
  const float absorption = look_light_absorption(look);
  const vec3 lo = vec3(-0.5), hi = vec3(size) + 0.5;
  const vec3 centre = vec3(x, y, z) + 0.5;
  const vec2 range = samples_in_box(centre, toward, texelFetch(box, 0).xyz, texelFetch(box, 1).xyz);
  float optical = 0.0;
  for (float j = first_sample_in(range); j <= range.y; j += 1.0) {
    const vec3 p = centre + j * toward;
    if (any(lessThanEqual(p, lo)) || any(greaterThanEqual(p, hi))) break;
    optical += sample_zero_quads(density, quads, size, p);
  }
  transmittance[item] = exp(-absorption * step_length * optical);
}
