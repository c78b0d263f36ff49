// The exact adjoint of one ray of march.comp, given the forward image I and g = dL/dimage. The march is
// recomputed front to back, so nothing per sample is stored:
//   R_k = I - sum_{j <= k} T_j a_j S_j                  radiance that reaches the camera from behind sample k
//   dI/dsigma_k = absorption * step * (T_{k+1} S_k - R_k)
//   dI/dS_k     = T_k a_k
// and each sample's gradients are added with the trilinear weights of p_k (a ray in a row of voxel centres
// reads and adds into four corners per sample, sampling.glsl):
//   grad_density[corner]       += g * dI/dsigma_k * w_corner        (zero padding)
//   grad_transmittance[corner] += g * intensity * dI/dS_k * w_corner (clamped lookup; LIGHT only)
// The including kernel declares the bindings density, light_transmittance, cameras, image, grad_image and
// look, the push constants width, height, depth, image_width, image_height and step_length, the constant
// LIGHT, and the functions that add into the gradients:
//   void add_density(ivec3 size, vec3 p, float value, const bool in_row);
//   void add_transmittance(ivec3 size, vec3 p, float value);
#ifndef SMOKESVD_RENDER_MARCH_ADJOINT_RAY_GLSL
#define SMOKESVD_RENDER_MARCH_ADJOINT_RAY_GLSL

// The march state of one ray and what its gradients are scaled by.
struct AdjointRay {
  float g, total, absorption, ambient, intensity;
  float accumulated, transmittance;
};

// One sample of the recomputed march: advances the state and gives the sample's density gradient and (LIGHT)
// transmittance gradient, to be added with the sample's own lookup weights.
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

// The samples of the ray (origin, direction), their gradients added; in_row: the ray runs in a
// row of voxel centres (ray_in_voxel_row), so every sample reads and adds into the four corners of its row.
void march_ray_adjoint(inout AdjointRay ray, vec3 origin, vec3 direction, const bool in_row) {
  const ivec3 size = ivec3(width, height, depth);
  const vec2 span = ray_box(origin, direction, vec3(-0.5), vec3(size) + 0.5);
  float density_grad, transmittance_grad;
  for (float t = span.x + 0.5 * step_length; t < span.y; t += step_length) {
    const vec3 p = origin + t * direction;
    const float sigma = in_row ? sample_zero_in_row(density, size, p) : sample_zero(density, size, p);
    adjoint_sample(ray, p, sigma, density_grad, transmittance_grad);
    add_density(size, p, density_grad, in_row);
    if (LIGHT != 0) add_transmittance(size, p, transmittance_grad);
  }
}

// The ray of pixel `item` (view, row, column) of the images and its march state; false where its g is 0
// (nothing to add).
bool pixel_ray(uint item, out AdjointRay ray, out vec3 origin, out vec3 direction) {
  const float g = texelFetch(grad_image, int(item)).x;
  if (g == 0.0) return false;
  const int column = int(item) % image_width;
  const int row = (int(item) / image_width) % image_height;
  const int view = int(item) / (image_width * image_height);
  ray = AdjointRay(g, texelFetch(image, int(item)).x, look_absorption(look), look_ambient(look), look_intensity(look),
                   0.0, 1.0);
  camera_ray(cameras, view, vec2(column, row) + 0.5, origin, direction);
  return true;
}

#endif
