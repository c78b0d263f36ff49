#version 450
#extension GL_GOOGLE_include_directive : require
// Upsampling by k in one pass, for inputs whose width W is a multiple of 4 (stencils of
// resample_stencil.glsl; the separable passes resample_x / resample_rows handle every other case).
// Along y (and z in 3D) outputs are grouped in cells that read the same two input rows:
//   linear:  cell c in [0, n] holds the k outputs o in [k (c - 1) + k/2, k c + k/2) (clipped to [0, kn)),
//            which all interpolate input rows max(c - 1, 0) and min(c, n - 1)
//   nearest: cell c in [0, n) holds outputs [k c, k c + k), which all copy input row c
// One invocation handles input texel p of a row (4 input columns, i.e. 4k output columns) for one y-cell
// and one z-cell: it reads each of the (up to) 2 x 2 input rows as a window of 6 columns [4p - 1, 4p + 4]
// (one vec4 texel and two neighbours, clamped to the row), and for each of the k x k output rows of the
// cells blends them along z and y, then along x with constant weights: output column 4kp + t has source
// position 4p + (2t + 1 - k) / 2k (linear) or 4p + t / k (nearest).
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
  ivec3 outSize;     // (kW, kH, kD or 1)
  uint items;        // planes * cells.z * cells.y * texelsPerRow
  ivec2 cells;       // cells along y and z
};

const int ROWS = MODE == 0 ? 1 : 2;  // input rows per cell

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
  const int j0 = num >= 0 ? num / (2 * FACTOR) : -1;  // num >= 1 - k > -2k
  return mix(column(w, j0), column(w, j0 + 1), float(num - j0 * 2 * FACTOR) / float(2 * FACTOR));
}

// The input row of cell c read as its row r (0: lower, 1: upper), and the first output of the cell.
int cellRow(int c, int r, int n) { return MODE == 0 ? c : r == 0 ? max(c - 1, 0) : min(c, n - 1); }
int cellFirst(int c) { return MODE == 0 ? FACTOR * c : FACTOR * (c - 1) + FACTOR / 2; }

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / texelsPerRow;
  const int p = int(item) - row * texelsPerRow;
  const int layer = row / cells.x;  // plane * cells.z + zCell
  const int yCell = row - layer * cells.x;
  const int plane = layer / cells.y;
  const int zCell = layer - plane * cells.y;

  Window rows[2][2];  // [z row][y row]
  for (int rz = 0; rz < (DIMS == 3 ? ROWS : 1); ++rz)
    for (int ry = 0; ry < ROWS; ++ry) {
      const int iz = DIMS == 3 ? cellRow(zCell, rz, inSize.z) : 0;
      rows[rz][ry] = window(((plane * inSize.z + iz) * inSize.y + cellRow(yCell, ry, inSize.y)) * inSize.x, p);
    }

  for (int tz = 0; tz < (DIMS == 3 ? FACTOR : 1); ++tz) {
    const int oz = DIMS == 3 ? cellFirst(zCell) + tz : 0;
    if (oz < 0 || oz >= outSize.z) continue;
    const float wz = DIMS == 3 && MODE != 0 ? stencil(oz, inSize.z).w : 0.0;
    const Window zy0 = DIMS == 3 && MODE != 0 ? blend(rows[0][0], rows[1][0], wz) : rows[0][0];
    const Window zy1 = DIMS == 3 && MODE != 0 ? blend(rows[0][1], rows[1][1], wz) : rows[0][1];
    for (int ty = 0; ty < FACTOR; ++ty) {
      const int oy = cellFirst(yCell) + ty;
      if (oy < 0 || oy >= outSize.y) continue;
      const Window w = MODE != 0 ? blend(zy0, zy1, stencil(oy, inSize.y).w) : zy0;
      const int outTexel = (((plane * outSize.z + oz) * outSize.y + oy) * outSize.x) / 4 + FACTOR * p;
      for (int q = 0; q < FACTOR; ++q)
        y[outTexel + q] = vec4(interpolate(w, 4 * q), interpolate(w, 4 * q + 1), interpolate(w, 4 * q + 2),
                               interpolate(w, 4 * q + 3));
    }
  }
}
