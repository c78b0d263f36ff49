#version 450
#extension GL_GOOGLE_include_directive : require
// The transpose of upsampling by k along W, for input widths that are multiples of 4:
//   gx[r, i] = sum_o weight(o, i) gy[r, o]    (weight: resample_stencil.glsl)
// One invocation writes input texel p of row r (columns 4p .. 4p + 3) from the gy texels holding output
// columns 4kp + t, t in [T_BEGIN, T_END). Relative to column 4p, output t reads columns j0 (weight 1 - w)
// and j0 + 1 (weight w), constants of t:
//   linear:   j0 = floor((2t + 1 - k) / 2k), w = the remainder / 2k;   t in [-(k + 1) / 2, 9k / 2) reaches
//             exactly the columns j in [-1, 4]
//   nearest:  j0 = t / k, w = 0;                                         t in [0, 4k)
// Outputs outside the row (t < 0 at p = 0, t >= 4k at the last p) are not read; there the clamped border
// outputs give their whole weight to the edge column: contributions to j = -1 fold into column 0 when
// p = 0, those to j = 4 into column 3 at the last p (elsewhere they belong to the neighbouring texel).
// Specialization constants: MODE (3) 0 nearest, 1 linear; FACTOR (4) k.
// Bindings: gy (vec4 texels), gx (storage, vec4).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int FACTOR = 2;

layout(binding = 0) uniform samplerBuffer gy;
layout(std430, binding = 1) writeonly buffer Output { vec4 gx[]; };
layout(push_constant) uniform Push {
  int texelsPerRow;  // input width / 4
  uint items;        // rows times texelsPerRow
};

const int T_BEGIN = MODE == 0 ? 0 : -(FACTOR + 1) / 2;
const int T_END = MODE == 0 ? 4 * FACTOR : 9 * FACTOR / 2;
const int FIRST_TEXEL = T_BEGIN < 0 ? -((3 - T_BEGIN) / 4) : T_BEGIN / 4;  // floor(T_BEGIN / 4)
const int TEXELS = (T_END + 3) / 4 - FIRST_TEXEL;

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / texelsPerRow;
  const int p = int(item) - row * texelsPerRow;
  const int rowTexels = FACTOR * texelsPerRow;  // output texels per row
  const int base = row * rowTexels + FACTOR * p;   // output texel of column 4kp
  vec4 texels[TEXELS];
  for (int k = 0; k < TEXELS; ++k) {
    const int relative = FACTOR * p + FIRST_TEXEL + k;  // within the row
    texels[k] = relative >= 0 && relative < rowTexels ? texelFetch(gy, base + FIRST_TEXEL + k) : vec4(0.0);
  }

  float left = 0.0, right = 0.0;  // contributions to columns -1 and 4
  vec4 sum = vec4(0.0);           // to columns 0 .. 3
  for (int t = T_BEGIN; t < T_END; ++t) {
    const float g = texels[(t - 4 * FIRST_TEXEL) / 4][(t - 4 * FIRST_TEXEL) % 4];
    int j0;
    float w;
    if (MODE == 0) {
      j0 = t / FACTOR;
      w = 0.0;
    } else {
      const int num = 2 * t + 1 - FACTOR;
      j0 = num >= 0 ? num / (2 * FACTOR) : (num + 1) / (2 * FACTOR) - 1;
      w = float(num - j0 * 2 * FACTOR) / float(2 * FACTOR);
    }
    const vec2 share = vec2(1.0 - w, w) * g;  // to columns j0 and j0 + 1
    if (j0 < 0) left += share.x;
    else sum[j0] += share.x;
    if (j0 + 1 > 3) right += share.y;
    else sum[j0 + 1] += share.y;
  }
  if (p == 0) sum.x += left;
  if (p + 1 == texelsPerRow) sum.w += right;
  gx[item] = sum;
}
