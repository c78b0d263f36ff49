#version 450
#extension GL_GOOGLE_include_directive : require
// Zero padding for the direct convolution:
//   xp[q, z, y, x] = src[q, z - lowZ, y - lowY, x - lowX] where that lies inside src, else 0,
// q = n*C + c over [Q, D, H, W] -> [Q, Dp, Hp, Wp]. Wp is a multiple of 4, so one invocation writes
// four consecutive x of one row of xp as a vec4.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Padded { vec4 xp[]; };
layout(push_constant) uniform Push {
  int depth, height, width;           // D, H, W
  int paddedDepth, paddedHeight;      // Dp, Hp
  int paddedRowVec4s;                 // Wp / 4
  int lowZ, lowY, lowX;               // padding before the first element
  int count;                          // number of vec4s in xp
};

void main() {
  const int item = int(flat_index());
  if (item >= count) return;
  const int x0 = (item % paddedRowVec4s) * 4 - lowX;
  const int row = item / paddedRowVec4s;
  const int sy = row % paddedHeight - lowY;
  const int plane = row / paddedHeight;
  const int sz = plane % paddedDepth - lowZ;
  const int q = plane / paddedDepth;
  vec4 v = vec4(0.0);
  if (sz >= 0 && sz < depth && sy >= 0 && sy < height) {
    const int source = ((q * depth + sz) * height + sy) * width;
    for (int i = 0; i < 4; ++i) {
      const int sx = x0 + i;
      if (sx >= 0 && sx < width) v[i] = texelFetch(src, source + sx).x;
    }
  }
  xp[item] = v;
}
