#version 450
#extension GL_GOOGLE_include_directive : require
// Lifting: each view's image spread along its camera rays into the volume.
//   lifted[v, z, y, x] = image_v(u, v_)  with (u, v_) the pixel coordinates of the voxel centre in camera v,
// read bilinearly at pixel centres (c + 1/2, r + 1/2) with zero padding outside the image; 0 for voxels
// behind a perspective camera. images [V, 1, h, w]; lifted [V, D, H, W] (views become channels).
// One invocation per column (v, z, x) walks y, reading the view's projection once. Where the image rows are
// the grid's rows of voxel centres (projection_in_pixel_rows: orbit cameras of the volume's height) the lower
// row's weight is 0 at every voxel and a loop of its own reads two pixels per voxel instead of four: the same
// value, since (1 - 0) a + 0 b = a.
#include "index.glsl"
#include "camera.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer images;
layout(binding = 1) uniform samplerBuffer cameras;
layout(std430, binding = 2) writeonly buffer Lifted { float lifted[]; };
layout(push_constant) uniform Push {
  int width, height, depth;
  int image_width, image_height, views;
};

float pixel_value(int view, ivec2 pixel) {
  if (any(lessThan(pixel, ivec2(0))) || pixel.x >= image_width || pixel.y >= image_height) return 0.0;
  return texelFetch(images, (view * image_height + pixel.y) * image_width + pixel.x).x;
}

// The bilinear read of the image at the pixel coordinates; one_row where the lower row's weight is known to be 0.
float bilinear(int view, vec2 pixel, const bool one_row) {
  const vec2 q = pixel - 0.5;
  const vec2 fl = floor(q);
  const vec2 f = q - fl;
  const ivec2 base = ivec2(fl);
  const float upper = (1.0 - f.x) * pixel_value(view, base) + f.x * pixel_value(view, base + ivec2(1, 0));
  if (one_row) return (1.0 - f.y) * upper;
  return (1.0 - f.y) * upper +
         f.y * ((1.0 - f.x) * pixel_value(view, base + ivec2(0, 1)) + f.x * pixel_value(view, base + ivec2(1, 1)));
}

void main() {
  const uint item = flat_index();
  if (item >= uint(views * depth * width)) return;
  const int view = int(item) / (depth * width);
  const int z = (int(item) / width) % depth;
  const int x = int(item) % width;
  const mat3x4 rows = camera_projection(cameras, view);
  const int column = ((view * depth + z) * height) * width + x;
  vec2 pixel;
  if (projection_in_pixel_rows(rows)) {
    for (int y = 0; y < height; ++y)
      lifted[column + y * width] = project(rows, vec3(x, y, z) + 0.5, pixel) ? bilinear(view, pixel, true) : 0.0;
  } else {
    for (int y = 0; y < height; ++y)
      lifted[column + y * width] = project(rows, vec3(x, y, z) + 0.5, pixel) ? bilinear(view, pixel, false) : 0.0;
  }
}
