#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of lift.comp w.r.t. the images (lift_adjoint.glsl has the formula) for a view set whose every
// projection maps voxel rows onto pixel rows (ViewSet::raysInVoxelRows: projection row 1 = (0, -1, 0, s)).
// Voxel plane y projects onto pixel row s - 1 - y of each view, at f.y = 0, so each voxel adds into the two
// pixels of that row either side of its projection (the row below has weight 0):
//   grad_images[v, 0, r, c]     += grad_lifted[v, z, y, x] * (1 - f.x)
//   grad_images[v, 0, r, c + 1] += grad_lifted[v, z, y, x] * f.x
// One invocation per plane y adds its voxels' gradients with plain read-modify-writes, since no other
// invocation writes those rows: no atomics, no shards, the same sums on every run. grad_images must be zero
// before the first dispatch; each dispatch takes views [first_view, first_view + view_count), so that an
// invocation stays under llvmpipe's loop limit (runtime/device_info.h).
#include "index.glsl"
#include "camera.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer grad_lifted;
layout(binding = 1) uniform samplerBuffer cameras;
layout(std430, binding = 2) buffer GradImages { float grad_images[]; };
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
  int first_view, view_count;
};

void add(int row_start, int column, float value) {
  if (column >= 0 && column < image_width && value != 0.0) grad_images[row_start + column] += value;
}

void main() {
  const int plane = int(gl_GlobalInvocationID.x);
  if (plane >= height) return;
  for (int view = first_view; view < first_view + view_count; ++view) {
    const mat3x4 rows = camera_projection(cameras, view);
    const int row = int(rows[1].w) - 1 - plane;
    if (row < 0 || row >= image_height) continue;
    const int row_start = (view * image_height + row) * image_width;
    for (int z = 0; z < depth; ++z) {
      const int first = ((view * depth + z) * height + plane) * width;
      for (int x = 0; x < width; ++x) {
        const float g = texelFetch(grad_lifted, first + x).x;
        vec2 pixel;
        if (g == 0.0 || !project(rows, vec3(x, plane, z) + 0.5, pixel)) continue;
        const float q = pixel.x - 0.5;
        const float fl = floor(q);
        const float f = q - fl;
        add(row_start, int(fl), g * (1.0 - f));
        add(row_start, int(fl) + 1, g * f);
      }
    }
  }
}
