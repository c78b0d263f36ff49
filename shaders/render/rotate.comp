#version 450
#extension GL_GOOGLE_include_directive : require
// Rotation of a volume about the vertical line through its centre c, trilinear with zero padding:
//   out[ch, q] = in[ch](c + R (c_q - c)),  R (dx, dy, dz) = (dx cos a - dz sin a, dy, dx sin a + dz cos a)
// so that the orbit camera at angle 0 sees `out` as the orbit camera at angle a sees `in` (pipeline/camera).
// ch: channel, q: output voxel, c_q its centre. One invocation per output value on a 3D grid:
// (x, y, z + D * ch); volumes [C, D, H, W].
#include "sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer volume;
layout(std430, binding = 1) writeonly buffer Rotated { float rotated[]; };
layout(push_constant) uniform Push {
  int width, height, depth, channels;
  float cos_a, sin_a;
};

void main() {
  const ivec3 id = ivec3(gl_GlobalInvocationID);
  if (id.x >= width || id.y >= height || id.z >= depth * channels) return;
  const int channel = id.z / depth;
  const ivec3 size = ivec3(width, height, depth);
  const ivec3 voxel = ivec3(id.x, id.y, id.z - channel * depth);
  const vec3 c = 0.5 * vec3(size);
  const vec3 d = vec3(voxel) + 0.5 - c;
  const vec3 source = c + vec3(d.x * cos_a - d.z * sin_a, d.y, d.x * sin_a + d.z * cos_a);
  const int voxels = width * height * depth;
  rotated[channel * voxels + voxel_index(voxel, size)] = sample_zero_at(volume, channel * voxels, size, source);
}
