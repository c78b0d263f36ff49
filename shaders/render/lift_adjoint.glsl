// Adjoint of lift.comp w.r.t. the images (one invocation per lifted value):
//   grad_images[v, 0, r, c] += grad_lifted[v, z, y, x] * w_(r, c)
// with w the bilinear weights lift.comp used for voxel (x, y, z) in view v. A scatter (float atomics): the voxels
// that read one pixel lie along its ray, a set with no regular layout under perspective cameras.
// grad_images must be zero before the dispatch. The invocations stride over the values; with
// shard_size > 0 each workgroup adds into its own copy of grad_images (elements from workgroup *
// shard_size on), a deterministic sum (pipeline/render/atomics.h).
#include "float_atomic_add.glsl"
#include "index.glsl"
#include "camera.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer grad_lifted;
layout(binding = 1) uniform samplerBuffer cameras;
layout(std430, binding = 2) buffer GradImages { float_atomic_t grad_images[]; };
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
  int shard_size;  // elements of one workgroup's copy of grad_images; 0: every workgroup adds into one
};

void scatter(int view, ivec2 pixel, float value) {
  if (any(lessThan(pixel, ivec2(0))) || pixel.x >= image_width || pixel.y >= image_height || value == 0.0) return;
  const int index = int(gl_WorkGroupID.x) * shard_size + (view * image_height + pixel.y) * image_width + pixel.x;
  float_atomic_add(grad_images, index, value);
}

void adjoint_value(uint item) {
  const int voxels = width * height * depth;
  const float g = texelFetch(grad_lifted, int(item)).x;
  if (g == 0.0) return;
  const int view = int(item) / voxels;
  const int voxel = int(item) % voxels;
  const vec3 centre = vec3(voxel % width, (voxel / width) % height, voxel / (width * height)) + 0.5;
  vec2 pixel;
  if (!camera_project(cameras, view, centre, pixel)) return;
  const vec2 q = pixel - 0.5;
  const vec2 fl = floor(q);
  const vec2 f = q - fl;
  const ivec2 base = ivec2(fl);
  scatter(view, base, g * (1.0 - f.x) * (1.0 - f.y));
  scatter(view, base + ivec2(1, 0), g * f.x * (1.0 - f.y));
  scatter(view, base + ivec2(0, 1), g * (1.0 - f.x) * f.y);
  scatter(view, base + ivec2(1, 1), g * f.x * f.y);
}

void main() {
  const uint values = uint(views * width * height * depth);
  for (uint item = flat_index(); item < values; item += flat_invocations()) adjoint_value(item);
}
