#version 450
#extension GL_GOOGLE_include_directive : require
// Output gradient in rows with channels last, for the weight gradient:
//   gT[m, x, k] = g[n, k, m - n*rowsPerItem, x]   for x < W and k < K, else 0
// m = (n, z, y) a row of g [N, K, D, H, W] (rowsPerItem = D*H); gT is [N*D*H, Wpad, Kpad], Kpad a
// multiple of 4. One invocation writes one vec4 of four consecutive k.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer g;
layout(std430, binding = 1) writeonly buffer Packed { vec4 gT[]; };
layout(push_constant) uniform Push {
  int channels;     // K
  int rowsPerItem;  // D*H
  int width;        // W
  int paddedWidth;  // Wpad
  int channelVec4s; // Kpad / 4
  int count;        // number of vec4s in gT
};

void main() {
  const int item = int(flat_index());
  if (item >= count) return;
  const int k0 = (item % channelVec4s) * 4;
  const int position = item / channelVec4s;
  const int x = position % paddedWidth;
  const int m = position / paddedWidth;
  const int n = m / rowsPerItem;
  const int plane = rowsPerItem * width;
  const int source = n * channels * plane + (m - n * rowsPerItem) * width + x;
  vec4 v = vec4(0.0);
  if (x < width) {
    for (int lane = 0; lane < 4; ++lane) {
      const int k = k0 + lane;
      if (k < channels) v[lane] = texelFetch(g, source + k * plane).x;
    }
  }
  gT[item] = v;
}
