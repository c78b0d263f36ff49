#version 450
#extension GL_GOOGLE_include_directive : require
// First stage of the bias gradient db[k] = sum_n sum_p g[n, k, p]:
//   partial[j, k] = sum over the chunk j of the flat positions i = n*P + p of g[n, k, p]
// with g [N, K, P] and chunks of chunkSize positions. One invocation per (j, k), k fastest.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer g;
layout(std430, binding = 1) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push {
  int channels;   // K
  int plane;      // P
  int positions;  // N*P
  int chunkSize;
  int count;      // chunks * K
};

void main() {
  const int item = int(flat_index());
  if (item >= count) return;
  const int k = item % channels;
  const int begin = (item / channels) * chunkSize;
  const int end = min(begin + chunkSize, positions);
  float sum = 0.0;
  int i = begin;
  while (i < end) {
    const int n = i / plane;
    const int runEnd = min(end, (n + 1) * plane);
    const int base = (n * channels + k) * plane - n * plane;
    for (; i < runEnd; ++i) sum += texelFetch(g, base + i).x;
  }
  partial[item] = sum;
}
