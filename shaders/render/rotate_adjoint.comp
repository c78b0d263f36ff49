#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of rotate.comp as a gather (one invocation per input value):
//   grad_in[ch, p] = sum_q grad_out[ch, q] * tent(s_q.x - c_p.x) * tent(s_q.z - c_p.z) * [q.y == p.y]
// with s_q = c + R (c_q - c) the sample point of output voxel q and tent(t) = max(0, 1 - |t|); the y weight is
// exact because rotation keeps y, and voxel centres sit on the integer lattice + 1/2. The q with a non-zero
// weight have s_q within 1 of c_p in x and z, so q lies within |cos a| + |sin a| of R^-1 (c_p - c) + c.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer grad_rotated;
layout(std430, binding = 1) writeonly buffer GradVolume { float grad_volume[]; };
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
  const int y = (voxel / width) % height;
  const vec2 c = 0.5 * vec2(width, depth);
  const vec2 p = vec2(voxel % width, voxel / (width * height)) + 0.5;  // (x, z) centre
  const vec2 d = p - c;
  const vec2 q = c + vec2(d.x * cos_a + d.y * sin_a, -d.x * sin_a + d.y * cos_a);  // R^-1 applied in (x, z)
  const float reach = abs(cos_a) + abs(sin_a);
  const ivec2 lo = max(ivec2(ceil(q - reach - 0.5)), ivec2(0));
  const ivec2 hi = min(ivec2(floor(q + reach - 0.5)), ivec2(width, depth) - 1);
  float sum = 0.0;
  for (int qz = lo.y; qz <= hi.y; ++qz) {
    for (int qx = lo.x; qx <= hi.x; ++qx) {
      const vec2 e = vec2(qx, qz) + 0.5 - c;
      const vec2 s = c + vec2(e.x * cos_a - e.y * sin_a, e.x * sin_a + e.y * cos_a);
      const vec2 w = max(vec2(0.0), 1.0 - abs(s - p));
      if (w.x * w.y != 0.0)
        sum += w.x * w.y * texelFetch(grad_rotated, channel * voxels + (qz * height + y) * width + qx).x;
    }
  }
  grad_volume[item] = sum;
}
