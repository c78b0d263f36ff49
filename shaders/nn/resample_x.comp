#version 450
#extension GL_GOOGLE_include_directive : require
// Resampling along the fastest axis (W): rows of n contiguous elements become rows of m
// (stencil, weight: resample_stencil.glsl):
//   forward   y[r, o] = (1 - w(o)) x[r, i0(o)] + w(o) x[r, i1(o)]
//   backward  gx[r, i] = sum_{o in candidates(i)} weight(o, i) gy[r, o]
// Each invocation writes 4 consecutive elements of one row (item = (row, quad)), gathering scalars;
// with ALIGNED (written row length % 4 == 0) the quad is stored as one vec4.
// Specialization constants: MODE, DOWN, FACTOR (resample_stencil.glsl), BACKWARD, ALIGNED.
// Bindings: source (float texels: x forward, gy backward), out (y forward, gx backward).
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
  int n;            // input row length
  int m;            // output row length
  int quadsPerRow;  // ceil(written row length / 4)
  uint items;       // rows times quadsPerRow
};
#include "resample_stencil.glsl"

float at(int row, int length, int index) { return texelFetch(source, row * length + index).r; }

// Element j of written row `row`; zero past the row's end.
float element(int row, int j) {
  float value = 0.0;
  if (BACKWARD == 0 && j < m) {
    const Stencil s = stencil(j, n);
    value = at(row, n, s.i0);
    if (s.w != 0.0) value = mix(value, at(row, n, s.i1), s.w);
  } else if (BACKWARD != 0 && j < n) {
    const ivec2 range = candidates(j, m);
    for (int o = range.x; o < range.y; ++o) {
      const float w = weight(o, j, n);
      if (w != 0.0) value += w * at(row, m, o);
    }
  }
  return value;
}

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / quadsPerRow;
  const int first = 4 * (int(item) - row * quadsPerRow);
  const int length = BACKWARD != 0 ? n : m;  // of the rows written
  const vec4 value =
      vec4(element(row, first), element(row, first + 1), element(row, first + 2), element(row, first + 3));
  const int start = row * length + first;
  if (ALIGNED != 0) {
    result[start / 4] = value;
    return;
  }
  for (int k = 0; k < 4 && first + k < length; ++k) result[(start + k) / 4][(start + k) % 4] = value[k];
}
