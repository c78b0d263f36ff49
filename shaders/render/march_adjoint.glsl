// Exact adjoint of march.comp (one invocation per pixel), given the forward image I and g = dL/dimage.
// The march is recomputed front to back, so nothing per sample is stored:
//   R_k = I - sum_{j <= k} T_j a_j S_j                  radiance that reaches the camera from behind sample k
//   dI/dsigma_k = absorption * step * (T_{k+1} S_k - R_k)
//   dI/dS_k     = T_k a_k
// and the sample gradients are scattered with the trilinear weights of p_k (float atomics; a ray in a row of voxel
// centres reads and scatters four corners per sample, sampling.glsl):
//   grad_density[corner]       += g * dI/dsigma_k * w_corner        (zero padding)
//   grad_transmittance[corner] += g * intensity * dI/dS_k * w_corner (clamped lookup; LIGHT only)
// A gather would need every sample's gradient stored ([views, samples, H, W]), hence the scatter. The
// invocations stride over the pixels; with shard_size > 0 each workgroup adds into its own copy of the
// gradients (elements from workgroup * shard_size on), a deterministic sum (pipeline/render/atomics.h).
#include "float_atomic_add.glsl"
#include "index.glsl"
#include "sampling.glsl"
#include "camera.glsl"
#include "look.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int LIGHT = 0;

layout(binding = 0) uniform samplerBuffer density;
layout(binding = 1) uniform samplerBuffer light_transmittance;
layout(binding = 2) uniform samplerBuffer cameras;
layout(binding = 3) uniform samplerBuffer image;
layout(binding = 4) uniform samplerBuffer grad_image;
layout(std430, binding = 5) buffer GradDensity { float_atomic_t grad_density[]; };
layout(std430, binding = 6) buffer GradTransmittance { float_atomic_t grad_transmittance[]; };  // any tensor without LIGHT
layout(binding = 7) uniform samplerBuffer look;
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
  float step_length;
  int shard_size;  // elements of one workgroup's copy of the gradients; 0: every workgroup adds into one
};

int shard_base() { return int(gl_WorkGroupID.x) * shard_size; }

// in_row: a ray in a row of voxel centres (sampling.glsl), whose upper corners' weights are 0.
void scatter_density(ivec3 size, vec3 p, float value, const bool in_row) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  for (int corner = 0; corner < stencil_corners(in_row); ++corner) {
    const ivec3 offset = stencil_corner(corner, in_row);
    const ivec3 v = base + offset;
    if (voxel_inside(v, size))
      float_atomic_add(grad_density, shard_base() + voxel_index(v, size), corner_weight(offset, f) * value);
  }
}

void scatter_transmittance(ivec3 size, vec3 p, float value) {
  ivec3 base;
  vec3 f;
  trilinear_corners(clamp_to_centres(p, size), base, f);
  for (int corner = 0; corner < 8; ++corner) {
    const ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    const float w = corner_weight(offset, f);
    const int index = shard_base() + voxel_index(clamped_voxel(base + offset, size), size);
    if (w != 0.0) float_atomic_add(grad_transmittance, index, w * value);
  }
}

// The march state of one ray and what its gradients are scaled by.
struct AdjointRay {
  float g, total, absorption, ambient, intensity;
  float accumulated, transmittance;
};

// One sample of the recomputed march: advances the state and gives the sample's density gradient and (LIGHT)
// transmittance gradient, to be scattered with the sample's own lookup weights.
void adjoint_sample(inout AdjointRay ray, vec3 p, float sigma, out float density_grad, out float transmittance_grad) {
  const ivec3 size = ivec3(width, height, depth);
  const float shadow = LIGHT != 0 ? sample_clamped(light_transmittance, size, p) : 0.0;
  const float source = ray.ambient + ray.intensity * shadow;
  const float alpha = 1.0 - exp(-ray.absorption * sigma * step_length);
  const float emitted = ray.transmittance * alpha;
  ray.accumulated += emitted * source;
  const float next = ray.transmittance * (1.0 - alpha);
  const float behind = ray.total - ray.accumulated;
  density_grad = ray.g * ray.absorption * step_length * (next * source - behind);
  transmittance_grad = ray.g * ray.intensity * emitted;
  ray.transmittance = next;
}

void adjoint_ray(uint item) {
  const float g = texelFetch(grad_image, int(item)).x;
  if (g == 0.0) return;
  const int column = int(item) % image_width;
  const int row = (int(item) / image_width) % image_height;
  const int view = int(item) / (image_width * image_height);
  const ivec3 size = ivec3(width, height, depth);
  AdjointRay ray = AdjointRay(g, texelFetch(image, int(item)).x, look_absorption(look), look_ambient(look),
                              look_intensity(look), 0.0, 1.0);

  vec3 origin, direction;
  camera_ray(cameras, view, vec2(column, row) + 0.5, origin, direction);
  const vec2 span = ray_box(origin, direction, vec3(-0.5), vec3(size) + 0.5);
  float density_grad, transmittance_grad;
  if (ray_in_voxel_row(origin, direction)) {
    for (float t = span.x + 0.5 * step_length; t < span.y; t += step_length) {
      const vec3 p = origin + t * direction;
      adjoint_sample(ray, p, sample_zero_in_row(density, size, p), density_grad, transmittance_grad);
      scatter_density(size, p, density_grad, true);
      if (LIGHT != 0) scatter_transmittance(size, p, transmittance_grad);
    }
  } else {
    for (float t = span.x + 0.5 * step_length; t < span.y; t += step_length) {
      const vec3 p = origin + t * direction;
      adjoint_sample(ray, p, sample_zero(density, size, p), density_grad, transmittance_grad);
      scatter_density(size, p, density_grad, false);
      if (LIGHT != 0) scatter_transmittance(size, p, transmittance_grad);
    }
  }
}

void main() {
  const uint pixels = uint(views * image_height * image_width);
  for (uint item = flat_index(); item < pixels; item += flat_invocations()) adjoint_ray(item);
}
