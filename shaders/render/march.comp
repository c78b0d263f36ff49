#version 450
#extension GL_GOOGLE_include_directive : require
// Emission-absorption ray marching, every view of one volume in one dispatch (one invocation per pixel).
// View v, pixel (row r, column c): ray o + t d (unit d, grid coordinates, camera.glsl) clipped to the box
// [-1/2, N + 1/2] (where the zero-padded density can be non-zero) as [t0, t1]; samples at
// t_k = t0 + (k + 1/2) * step for t_k < t1, k = 0, 1, ...:
// The look (absorption, ambient, light intensity) is read from a small buffer so that one recording can
// render with other settings after an upload (look.glsl):
//   sigma_k = density(p_k)                      trilinear, zero padding
//   S_k     = ambient + intensity * T_L(p_k)    with LIGHT (T_L trilinear, clamped); else S_k = ambient
//   a_k     = 1 - exp(-absorption * sigma_k * step)
//   T_0 = 1, T_{k+1} = T_k (1 - a_k)
//   image[v, 0, r, c] = sum_k T_k a_k S_k
// Rays at the height of a row of voxel centres (orbit cameras) read four corners per sample (sampling.glsl).
// A sample outside the density's occupied box (occupied_box.glsl) has sigma_k = 0, so a_k = 0: it adds
// exactly 0 and leaves T as it is. The march steps t through those before the box without looking them up
// (t is a running sum, so its steps are kept) and stops after the box: the same image bit for bit.
#include "index.glsl"
#include "sampling.glsl"
#include "camera.glsl"
#include "look.glsl"
#include "occupied_box.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int LIGHT = 0;

layout(binding = 0) uniform samplerBuffer density;
layout(binding = 1) uniform samplerBuffer light_transmittance;  // [D, H, W]; any tensor without LIGHT
layout(binding = 2) uniform samplerBuffer cameras;              // vec4 texels
layout(std430, binding = 3) writeonly buffer Image { float image[]; };
layout(binding = 4) uniform samplerBuffer look;
layout(binding = 5) uniform samplerBuffer box;  // the density's occupied box: low, high (occupied_box.comp)
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
  float step_length;
};

// One sample of the march: accumulate its emission and attenuate the transmittance.
void accumulate(float sigma, vec3 p, float absorption, float ambient, float intensity, inout float radiance,
                inout float transmittance) {
  const ivec3 size = ivec3(width, height, depth);
  const float source = LIGHT != 0 ? ambient + intensity * sample_clamped(light_transmittance, size, p) : ambient;
  const float alpha = 1.0 - exp(-absorption * sigma * step_length);
  radiance += transmittance * alpha * source;
  transmittance *= 1.0 - alpha;
}

void main() {
  const uint item = flat_index();
  if (item >= uint(views * image_height * image_width)) return;
  const int column = int(item) % image_width;
  const int row = (int(item) / image_width) % image_height;
  const int view = int(item) / (image_width * image_height);
  const ivec3 size = ivec3(width, height, depth);
  const float absorption = look_absorption(look), ambient = look_ambient(look), intensity = look_intensity(look);

  vec3 origin, direction;
  camera_ray(cameras, view, vec2(column, row) + 0.5, origin, direction);
  const vec2 span = ray_box(origin, direction, vec3(-0.5), vec3(size) + 0.5);
  const vec2 occupied = samples_in_box(origin, direction, texelFetch(box, 0).xyz, texelFetch(box, 1).xyz);
  float first = span.x + 0.5 * step_length;
  while (first < occupied.x && first < span.y) first += step_length;
  float radiance = 0.0;
  float transmittance = 1.0;
  if (ray_in_voxel_row(origin, direction)) {
    for (float t = first; t < span.y && t <= occupied.y; t += step_length) {
      const vec3 p = origin + t * direction;
      accumulate(sample_zero_in_row(density, size, p), p, absorption, ambient, intensity, radiance, transmittance);
    }
  } else {
    for (float t = first; t < span.y && t <= occupied.y; t += step_length) {
      const vec3 p = origin + t * direction;
      accumulate(sample_zero(density, size, p), p, absorption, ambient, intensity, radiance, transmittance);
    }
  }
  image[item] = radiance;
}
