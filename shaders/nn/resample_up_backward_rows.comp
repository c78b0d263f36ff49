#version 450
#extension GL_GOOGLE_include_directive : require
// The transpose of upsampling by k along an outer axis (H or D) for rows of `inner` elements, inner a
// multiple of 4: gy [outer, k n, inner] -> gx [outer, n, inner] (stencils of resample_stencil.glsl).
// The outputs fall into cells that read the same two inputs: linear cell c in [0, n] holds the outputs
// [k (c - 1) + k/2, k c + k/2) (clipped to [0, k n)), which give weight 1 - w to input c - 1 and w to input
// c (at the borders, cells 0 and n give everything to input 0 and n - 1); nearest cell c = outputs
// [k c, k c + k), all to input c. One invocation writes RUN consecutive inputs i of one quad of a row,
// walking the cells in order so that every gy row is read once (not twice, as the row-wise transpose
// reads it), carrying the upper share of a cell to the next input.
// Specialization constants: MODE (3) 0 nearest, 1 linear; FACTOR (4) k.
// Bindings: gy (vec4 texels), gx (storage, vec4).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int FACTOR = 2;
const int DOWN = 0;
#include "resample_stencil.glsl"

layout(binding = 0) uniform samplerBuffer gy;
layout(std430, binding = 1) writeonly buffer Output { vec4 gx[]; };
layout(push_constant) uniform Push {
  int n;            // input rows along the axis (k n output rows)
  int quadsPerRow;  // inner / 4
  int runs;         // ceil(n / RUN)
  uint items;       // outer * runs * quadsPerRow
};

const int RUN = 8;

vec4 outputRow(int a, int o, int quad) { return texelFetch(gy, (a * FACTOR * n + o) * quadsPerRow + quad); }
void store(int a, int i, int quad, vec4 value) { gx[(a * n + i) * quadsPerRow + quad] = value; }

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / quadsPerRow;  // (a, run)
  const int quad = int(item) - row * quadsPerRow;
  const int a = row / runs;
  const int first = RUN * (row - a * runs);
  const int last = min(first + RUN, n);  // inputs [first, last)

  if (MODE == 0) {
    for (int i = first; i < last; ++i) {
      vec4 sum = vec4(0.0);
      for (int t = 0; t < FACTOR; ++t) sum += outputRow(a, FACTOR * i + t, quad);
      store(a, i, quad, sum);
    }
    return;
  }

  vec4 carry = vec4(0.0);  // the shares of cells so far that belong to input c - 1
  for (int c = first; c <= last; ++c) {
    vec4 low = vec4(0.0), high = vec4(0.0);  // shares of cell c for inputs c - 1 and c
    for (int t = 0; t < FACTOR; ++t) {
      const int o = FACTOR * (c - 1) + FACTOR / 2 + t;
      if (o < 0 || o >= FACTOR * n) continue;
      const float w = stencil(o, n).w;
      const vec4 g = outputRow(a, o, quad);
      low += (1.0 - w) * g;
      high += w * g;
    }
    if (c == 0) {
      carry = low + high;  // the clamped cell 0 belongs to input 0 alone
    } else if (c == first) {
      carry = high;        // its lower share belongs to the previous run
    } else {
      store(a, c - 1, quad, carry + low + (c == n ? high : vec4(0.0)));
      carry = high;
    }
  }
}
