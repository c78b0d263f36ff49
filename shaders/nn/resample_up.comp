#version 450
#extension GL_GOOGLE_include_directive : require
// Upsampling by k in one pass, for inputs whose width W is a multiple of 4 (stencils of
// resample_stencil.glsl; the separable passes resample_x / resample_rows handle every other case).
// One invocation handles input texel p of a row (4 input columns, i.e. 4k output columns) for one
// y-cell c and one output depth oz:
//   y-cell c in [0, H]: the k output rows o in [k (c - 1) + k/2, k c + k/2) (clipped to [0, kH)), which
//   all interpolate input rows max(c - 1, 0) and min(c, H - 1) (nearest: rows o / k = c, with k/2 = 0
//   offset: cell c is simply output rows [k c, k c + k) of input row c)
//   oz: its own stencil along D (3D) or none (2D).
// Input rows (2 along y times 2 along z, fewer for nearest) are read as windows of 6 columns
// [4p - 1, 4p + 4] (one vec4 texel and two neighbours, clamped to the row), blended along z, then for
// each output row of the cell along y, then along x with constant weights: output column 4kp + t has
// source position 4p + (2t + 1 - k) / 2k (linear) or 4p + t / k (nearest).
// Specialization constants: MODE (3) 0 nearest, 1 linear; FACTOR (4) k; DIMS (5) 2 or 3.
// Bindings: x (vec4 texels), y (storage, vec4).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int FACTOR = 2;
layout(constant_id = 5) const int DIMS = 3;
const int DOWN = 0;
#include "resample_stencil.glsl"

layout(binding = 0) uniform samplerBuffer x;
layout(std430, binding = 1) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push {
  ivec3 inSize;      // (W, H, D)
  int texelsPerRow;  // W / 4
  ivec3 outSize;     // (kW, kH, kD or D)
  int cells;         // y-cells per output depth: H + 1 (linear) or H (nearest)
  uint items;        // planes * outD * cells * texelsPerRow
};

struct Window {
  vec4 middle;  // columns 4p .. 4p + 3
  float left;   // column 4p - 1, or column 0 at the row start
  float right;  // column 4p + 4, or the last column at the row end
};

Window window(int rowStart, int p) {
  const vec4 middle = texelFetch(x, rowStart / 4 + p);
  const float left = p > 0 ? texelFetch(x, rowStart / 4 + p - 1).w : middle.x;
  const float right = p + 1 < texelsPerRow ? texelFetch(x, rowStart / 4 + p + 1).x : middle.w;
  return Window(middle, left, right);
}

Window blend(Window a, Window b, float w) {
  return Window(mix(a.middle, b.middle, w), mix(a.left, b.left, w), mix(a.right, b.right, w));
}

// Window column c in [-1, 4].
float column(Window w, int c) { return c < 0 ? w.left : c > 3 ? w.right : w.middle[c]; }

// Output column t in [0, 4k) of the texel's span.
float interpolate(Window w, int t) {
  if (MODE == 0) return column(w, t / FACTOR);
  const int num = 2 * t + 1 - FACTOR;
  const int i0 = num >= 0 ? num / (2 * FACTOR) : -1;  // num >= -FACTOR, so floor is -1 when negative
  const float frac = float(num - i0 * 2 * FACTOR) / float(2 * FACTOR);
  return mix(column(w, i0), column(w, i0 + 1), frac);
}

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / texelsPerRow;  // (plane, oz, cell)
  const int p = int(item) - row * texelsPerRow;
  const int layer = row / cells;             // plane * outD + oz
  const int cell = row - layer * cells;
  const int plane = layer / outSize.z;
  const int oz = layer - plane * outSize.z;

  const Stencil sz = DIMS == 3 ? stencil(oz, inSize.z) : Stencil(oz, oz, 0.0);
  const int yLow = MODE == 0 ? cell : max(cell - 1, 0);
  const int yHigh = MODE == 0 ? cell : min(cell, inSize.y - 1);
  Window rows[2];
  for (int r = 0; r < (MODE == 0 ? 1 : 2); ++r) {
    const int iy = r == 0 ? yLow : yHigh;
    const Window low = window(((plane * inSize.z + sz.i0) * inSize.y + iy) * inSize.x, p);
    rows[r] = sz.w != 0.0 ? blend(low, window(((plane * inSize.z + sz.i1) * inSize.y + iy) * inSize.x, p), sz.w) : low;
  }

  const int firstRow = MODE == 0 ? FACTOR * cell : FACTOR * (cell - 1) + FACTOR / 2;
  for (int ty = 0; ty < FACTOR; ++ty) {
    const int oy = firstRow + ty;
    if (oy < 0 || oy >= outSize.y) continue;
    const Window w = MODE == 0 ? rows[0] : blend(rows[0], rows[1], stencil(oy, inSize.y).w);
    const int outTexel = (((layer * outSize.y) + oy) * outSize.x) / 4 + FACTOR * p;
    for (int q = 0; q < FACTOR; ++q)
      y[outTexel + q] = vec4(interpolate(w, 4 * q), interpolate(w, 4 * q + 1), interpolate(w, 4 * q + 2),
                             interpolate(w, 4 * q + 3));
  }
}
