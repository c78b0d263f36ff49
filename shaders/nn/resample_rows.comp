#version 450
#extension GL_GOOGLE_include_directive : require
// Resampling along an outer axis (H or D of N,C,D,H,W): the tensor is seen as [outer, n, inner] and
// whole rows of `inner` contiguous elements are combined (stencil, weight: resample_stencil.glsl):
//   forward   y[a, o, b] = (1 - w(o)) x[a, i0(o), b] + w(o) x[a, i1(o), b]     y: [outer, m, inner]
//   backward  gx[a, i, b] = sum_{o in candidates(i)} weight(o, i) gy[a, o, b]    gx: [outer, n, inner]
// Each invocation writes SEGMENT consecutive quads (4 elements b each) of one row, item = (row, segment)
// with row = (a, o) forward and (a, i) backward, so the stencil is worked out once per 4 SEGMENT elements.
// Specialization constants (they remove the untaken paths, which lavapipe would otherwise run masked):
// MODE, DOWN, FACTOR (resample_stencil.glsl), BACKWARD, ALIGNED (inner % 4 == 0: rows read and written as
// vec4 texels).
// Bindings: source (texels: x forward, gy backward), out (y forward, gx backward).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;      // 0 nearest, 1 linear
layout(constant_id = 4) const int DOWN = 0;      // 0 up, 1 down
layout(constant_id = 5) const int FACTOR = 2;    // k
layout(constant_id = 6) const int BACKWARD = 0;  // 0 forward, 1 backward
layout(constant_id = 7) const int ALIGNED = 1;   // 1 when the rows written are vec4-aligned

layout(binding = 0) uniform samplerBuffer source;
layout(std430, binding = 1) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push {
  int n;               // input size along the axis
  int m;               // output size along the axis
  int inner;           // elements per row
  int quadsPerRow;     // ceil(inner / 4)
  int segmentsPerRow;  // ceil(quadsPerRow / SEGMENT)
  uint items;          // rows written times segmentsPerRow
};
#include "resample_stencil.glsl"

const int SEGMENT = 4;

// Elements [first, first + 4) of source row `row`; zero past the row's end.
vec4 load(int row, int first) {
  const int start = row * inner + first;
  if (ALIGNED != 0) return texelFetch(source, start / 4);
  vec4 value = vec4(0.0);
  value.x = texelFetch(source, start).r;
  if (first + 1 < inner) value.y = texelFetch(source, start + 1).r;
  if (first + 2 < inner) value.z = texelFetch(source, start + 2).r;
  if (first + 3 < inner) value.w = texelFetch(source, start + 3).r;
  return value;
}

void store(int row, int first, vec4 value) {
  const int start = row * inner + first;
  if (ALIGNED != 0) {
    result[start / 4] = value;
    return;
  }
  for (int k = 0; k < 4 && first + k < inner; ++k) result[(start + k) / 4][(start + k) % 4] = value[k];
}

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / segmentsPerRow;
  const int firstQuad = SEGMENT * (int(item) - row * segmentsPerRow);
  const int endQuad = min(firstQuad + SEGMENT, quadsPerRow);
  const int rowsPerOuter = BACKWARD != 0 ? n : m;
  const int a = row / rowsPerOuter;
  const int j = row - a * rowsPerOuter;  // o forward, i backward

  if (BACKWARD == 0) {
    const Stencil s = stencil(j, n);
    for (int q = firstQuad; q < endQuad; ++q) {
      vec4 value = load(a * n + s.i0, 4 * q);
      if (s.w != 0.0) value = mix(value, load(a * n + s.i1, 4 * q), s.w);
      store(row, 4 * q, value);
    }
    return;
  }
  const ivec2 range = candidates(j, m);
  vec4 value[SEGMENT];
  for (int q = 0; q < SEGMENT; ++q) value[q] = vec4(0.0);
  for (int o = range.x; o < range.y; ++o) {
    const float w = weight(o, j, n);
    if (w == 0.0) continue;
    for (int q = 0; q < SEGMENT; ++q)
      if (firstQuad + q < endQuad) value[q] += w * load(a * m + o, 4 * (firstQuad + q));
  }
  for (int q = 0; q < SEGMENT; ++q)
    if (firstQuad + q < endQuad) store(row, 4 * (firstQuad + q), value[q]);
}
