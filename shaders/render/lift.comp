#version 450
#extension GL_GOOGLE_include_directive : require
// Lifting: each view's image spread along its camera rays into the volume (one invocation per output value).
//   lifted[v, z, y, x] = image_v(u, v_)  with (u, v_) the pixel coordinates of the voxel centre in camera v,
// read bilinearly at pixel centres (c + 1/2, r + 1/2) with zero padding outside the image; 0 for voxels
// behind a perspective camera. images [V, 1, h, w]; lifted [V, D, H, W] (views become channels).
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

void main() {
  const uint item = flat_index();
  const int voxels = width * height * depth;
  if (item >= uint(views * voxels)) return;
  const int view = int(item) / voxels;
  const int voxel = int(item) % voxels;
  const vec3 centre = vec3(voxel % width, (voxel / width) % height, voxel / (width * height)) + 0.5;
  vec2 pixel;
  float value = 0.0;
  if (camera_project(cameras, view, centre, pixel)) {
    const vec2 q = pixel - 0.5;
    const vec2 fl = floor(q);
    const vec2 f = q - fl;
    const ivec2 base = ivec2(fl);
    value = (1.0 - f.y) * ((1.0 - f.x) * pixel_value(view, base) + f.x * pixel_value(view, base + ivec2(1, 0))) +
            f.y * ((1.0 - f.x) * pixel_value(view, base + ivec2(0, 1)) + f.x * pixel_value(view, base + ivec2(1, 1)));
  }
  lifted[item] = value;
}
