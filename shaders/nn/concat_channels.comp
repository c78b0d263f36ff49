#version 450
#extension GL_GOOGLE_include_directive : require
// Copies a run of channels between two N,C,... tensors (concatenation and slicing along axis 1):
//   dst[n*dstRow + dstOffset + j] = src[n*srcRow + srcOffset + j] for n < N, j < length,
// where a row is one sample (C*S floats, S the spatial size) and offsets and length are channel
// counts times S. Invocation i copies the elements e = 4i..4i+3 of the N*length copied, with
// n = e / length, j = e % length. VEC4 (constant_id 3): rows, offsets and length are multiples of 4,
// so the four share a sample and move as one vec4 texel.
#include "index.glsl"
#include "broadcast_index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool VEC4 = false;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Destination { vec4 dst[]; };  // single floats: dst[i / 4][i % 4]
layout(push_constant) uniform Push { uint total, srcRow, srcOffset, dstRow, dstOffset, length; uvec2 byLength; };

void main() {
  const uint item = flat_index();
  if (4u * item >= total) return;
  const uint first = 4u * item;
  const uint n = divide(first, byLength);
  const uint j = first - n * length;
  if (VEC4) {
    dst[(n * dstRow + dstOffset + j) / 4u] = texelFetch(src, int((n * srcRow + srcOffset + j) / 4u));
    return;
  }
  for (uint lane = 0u; lane < 4u && first + lane < total; ++lane) {
    const bool next = j + lane >= length;  // at most one sample boundary when length >= 4
    const uint m = length >= 4u ? n + uint(next) : divide(first + lane, byLength);
    const uint offset = first + lane - m * length;
    const uint to = m * dstRow + dstOffset + offset;
    dst[to / 4u][to % 4u] = texelFetch(src, int(m * srcRow + srcOffset + offset)).x;
  }
}
