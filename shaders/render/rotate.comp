#version 450
#extension GL_GOOGLE_include_directive : require
// Rotation of a volume about the vertical line through its centre c, trilinear with zero padding:
//   out[ch, q] = in[ch](c + R (c_q - c)),  R (dx, dy, dz) = (dx cos a - dz sin a, dy, dx sin a + dz cos a)
// so that the orbit camera at angle 0 sees `out` as the orbit camera at angle a sees `in` (pipeline/camera).
// ch: channel, q: output voxel, c_q its centre. One invocation per output value; volumes [C, D, H, W].
#include "index.glsl"
#include "sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer volume;
layout(std430, binding = 1) writeonly buffer Rotated { float rotated[]; };
layout(push_constant) uniform Push {
  int width, height, depth, channels;
  float cos_a, sin_a;
};

void main() {
  const uint item = flat_index();
  const int voxels = width * height * depth;
  if (item >= uint(channels * voxels)) return;
  const int channel = int(item) / voxels;
  const int voxel = int(item) % voxels;
  const ivec3 size = ivec3(width, height, depth);
  const vec3 c = 0.5 * vec3(size);
  const vec3 d = vec3(voxel % width, (voxel / width) % height, voxel / (width * height)) + 0.5 - c;
  const vec3 source = c + vec3(d.x * cos_a - d.z * sin_a, d.y, d.x * sin_a + d.z * cos_a);

  ivec3 base;
  vec3 f;
  trilinear_corners(source, base, f);
  float value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    const ivec3 v = base + offset;
    if (voxel_inside(v, size))
      value += corner_weight(offset, f) * texelFetch(volume, channel * voxels + voxel_index(v, size)).x;
  }
  rotated[item] = value;
}
