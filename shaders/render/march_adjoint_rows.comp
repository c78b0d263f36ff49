#version 450
#extension GL_GOOGLE_include_directive : require
// Exact adjoint of march.comp (march_adjoint_ray.glsl has the formulas) for a view set whose every ray runs
// along a row of voxel centres (ViewSet::raysInVoxelRows: orthographic orbit cameras with one pixel row per
// voxel row, origin per v = (0, -1, 0) and an integer origin height o.y). Pixel row r of such a view lies in
// the voxel plane y = o.y - 1 - r and its samples read and add into that plane alone, so one invocation per
// plane y marches the rays of its rows in views [first_view, first_view + view_count) and adds their
// gradients with plain read-modify-writes: no other invocation writes the plane, and the sums need neither
// atomics nor shards and come out the same on every run. The host splits the views over dispatches so that
// an invocation stays under llvmpipe's loop limit (runtime/device_info.h).
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
layout(std430, binding = 5) buffer GradDensity { float grad_density[]; };
layout(std430, binding = 6) buffer GradTransmittance { float grad_transmittance[]; };  // any tensor without LIGHT
layout(binding = 7) uniform samplerBuffer look;
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
  float step_length;
  int first_view, view_count;
};

// Only rays in rows reach here: the four corners of the sample's own row.
void add_density(ivec3 size, vec3 p, float value, const bool in_row) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  for (int corner = 0; corner < 4; ++corner) {
    const ivec3 offset = stencil_corner(corner, true);
    const ivec3 v = base + offset;
    if (voxel_inside(v, size)) grad_density[voxel_index(v, size)] += corner_weight(offset, f) * value;
  }
}

// The clamped lookup's corners in the row above have weight 0 (f.y = 0) and are skipped.
void add_transmittance(ivec3 size, vec3 p, float value) {
  ivec3 base;
  vec3 f;
  trilinear_corners(clamp_to_centres(p, size), base, f);
  for (int corner = 0; corner < 8; ++corner) {
    const ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    const float w = corner_weight(offset, f);
    if (w != 0.0) grad_transmittance[voxel_index(clamped_voxel(base + offset, size), size)] += w * value;
  }
}

#include "march_adjoint_ray.glsl"

void main() {
  const int plane = int(gl_GlobalInvocationID.x);
  if (plane >= height) return;
  for (int view = first_view; view < first_view + view_count; ++view) {
    const int row = int(texelFetch(cameras, view * CAMERA_TEXELS).y) - 1 - plane;
    if (row < 0 || row >= image_height) continue;
    for (int column = 0; column < image_width; ++column) {
      AdjointRay ray;
      vec3 origin, direction;
      if (pixel_ray(uint((view * image_height + row) * image_width + column), ray, origin, direction))
        march_ray_adjoint(ray, origin, direction, true);
    }
  }
}
