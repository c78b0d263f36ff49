#version 450
#extension GL_GOOGLE_include_directive : require
// Zero padding for the direct convolution, optionally through an activation f (the padding stays zero):
//   xp[q, z, y, x] = f(src[q, z - lowZ, y - lowY, x - lowX]) where that lies inside src, else 0,
//   ACTIVATION 0: f(v) = v;  1: leaky ReLU, f(v) = v > 0 ? v : slope v;
//   2: GroupNorm then SiLU, f(v) = SiLU((v - mean_b) a + beta[c]), a = rstd_b gamma[c], with (mean, rstd)
//      of group b = q / (C / G) from stats (ops::groupNormStats), the expression group_norm_apply evaluates,
// q = n*C + c over [Q, D, H, W] -> [Q, Dp, Hp, Wp]. One invocation writes one row y as vec4s (Wp is a
// multiple of 4); lanes run along y, workgroup y is the plane q*Dp + z, so the only division is
// shared by the workgroup. With VEC4_SOURCE (W a multiple of 4, src bound as vec4 texels) each output vec4
// is four consecutive source values, from the source vec4s a and a + 1 shifted by r = (-lowX) mod 4: one
// vec4 fetch per output vec4 (a + 1 is the next column's a) instead of four scalar ones.
// Bindings: src (texels), xp (storage), stats, gamma, beta (float texels, read with ACTIVATION 2 only; the
// host binds src in their place otherwise).
#include "sigmoid.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int ACTIVATION = 0;
layout(constant_id = 4) const bool VEC4_SOURCE = false;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Padded { vec4 xp[]; };
layout(binding = 2) uniform samplerBuffer stats;
layout(binding = 3) uniform samplerBuffer gamma;
layout(binding = 4) uniform samplerBuffer beta;
layout(push_constant) uniform Push {
  int depth, height, width;  // D, H, W
  int paddedDepth;           // Dp
  int paddedHeight;          // Hp
  int paddedRowVec4s;        // Wp / 4
  int lowZ, lowY, lowX;      // padding before the first element
  float slope;               // negative slope of f (ACTIVATION 1)
  int channels;              // C (ACTIVATION 2)
  int channelsPerGroup;      // C / G (ACTIVATION 2)
};

// The plane's normalisation (ACTIVATION 2): mean, a, b.
float normMean = 0.0, normScale = 1.0, normShift = 0.0;

// f of the four values v, of which those with `inside` set lie inside the source (the others are padding).
vec4 activated(vec4 v, bvec4 inside) {
  if (ACTIVATION == 1) return mix(slope * v, v, greaterThan(v, vec4(0.0)));
  if (ACTIVATION == 2) return mix(vec4(0.0), silu((v - normMean) * normScale + normShift), inside);
  return v;
}

// Source vec4 a of the row starting at vec4 `row_start`, 0 outside the row or where the row is padding.
vec4 source_vec4(bool inside, int row_start, int a) {
  if (inside && a >= 0 && a < width / 4) return texelFetch(src, row_start + a);
  return vec4(0.0);
}

// Four consecutive values starting at component r of a, continuing into b.
vec4 shifted(vec4 a, vec4 b, int r) {
  return r == 0 ? a : r == 1 ? vec4(a.yzw, b.x) : r == 2 ? vec4(a.zw, b.xy) : vec4(a.w, b.xyz);
}

// Which of the four columns 4 column + i - lowX (i = 0..3) of a row inside the source lie inside it.
bvec4 columnsInside(bool inside, int column) {
  const ivec4 sx = ivec4(4 * column - lowX) + ivec4(0, 1, 2, 3);
  return bvec4(uvec4(inside) & uvec4(greaterThanEqual(sx, ivec4(0))) & uvec4(lessThan(sx, ivec4(width))));
}

void main() {
  const int y = int(gl_GlobalInvocationID.x);
  if (y >= paddedHeight) return;
  const int plane = int(gl_WorkGroupID.y);
  const int q = plane / paddedDepth;
  const int sz = plane - q * paddedDepth - lowZ;
  const int sy = y - lowY;
  const bool inside = sz >= 0 && sz < depth && sy >= 0 && sy < height;
  const int source = ((q * depth + sz) * height + sy) * width;
  const int row = (plane * paddedHeight + y) * paddedRowVec4s;
  if (ACTIVATION == 2) {
    const int block = q / channelsPerGroup, c = q % channels;
    normMean = texelFetch(stats, 2 * block).r;
    normScale = texelFetch(stats, 2 * block + 1).r * texelFetch(gamma, c).r;
    normShift = texelFetch(beta, c).r;
  }
  if (VEC4_SOURCE) {
    // Output column j reads source values 4j - lowX + i = 4 (j - k) + r + i, k = (lowX + r) / 4.
    const int r = (-lowX) & 3, k = (lowX + r) / 4, row_start = source / 4;
    vec4 current = source_vec4(inside, row_start, -k);
    for (int column = 0; column < paddedRowVec4s; ++column) {
      const vec4 next = source_vec4(inside, row_start, column + 1 - k);
      xp[row + column] = activated(shifted(current, next, r), columnsInside(inside, column));
      current = next;
    }
    return;
  }
  for (int column = 0; column < paddedRowVec4s; ++column) {
    vec4 v = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
      const int sx = column * 4 + i - lowX;
      if (inside && sx >= 0 && sx < width) v[i] = texelFetch(src, source + sx).x;
    }
    xp[row + column] = activated(v, columnsInside(inside, column));
  }
}
