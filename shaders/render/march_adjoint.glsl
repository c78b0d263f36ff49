// Exact adjoint of march.comp (one invocation per pixel; march_adjoint_ray.glsl has the formulas), its
// gradients scattered with float atomics, since rays of different pixels add into the same voxels. A gather
// would need every sample's gradient stored ([views, samples, H, W]), hence the scatter. The invocations
// stride over the pixels; with shard_size > 0 each workgroup adds into its own copy of the gradients
// (elements from workgroup * shard_size on), a deterministic sum (pipeline/render/atomics.h).
// march_adjoint_rows.comp is the atomic-free variant for view sets whose rays all run in rows of voxel centres.
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
void add_density(ivec3 size, vec3 p, float value, const bool in_row) {
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

void add_transmittance(ivec3 size, vec3 p, float value) {
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

#include "march_adjoint_ray.glsl"

void main() {
  const uint pixels = uint(views * image_height * image_width);
  for (uint item = flat_index(); item < pixels; item += flat_invocations()) {
    AdjointRay ray;
    vec3 origin, direction;
    if (!pixel_ray(item, ray, origin, direction)) continue;
    if (ray_in_voxel_row(origin, direction))
      march_ray_adjoint(ray, origin, direction, true);
    else
      march_ray_adjoint(ray, origin, direction, false);
  }
}
