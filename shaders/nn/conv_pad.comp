#version 450
// Zero padding for the direct convolution, optionally through leaky ReLU (ACTIVATE; f(0) = 0, so the
// padding stays zero):
//   xp[q, z, y, x] = f(src[q, z - lowZ, y - lowY, x - lowX]) where that lies inside src, else 0,
//   f(v) = v > 0 ? v : slope v when ACTIVATE, else v,
// q = n*C + c over [Q, D, H, W] -> [Q, Dp, Hp, Wp]. One invocation writes one row y as vec4s (Wp is a
// multiple of 4); lanes run along y, workgroup y is the plane q*Dp + z, so the only division is
// shared by the workgroup. With VEC4_SOURCE (W a multiple of 4, src bound as vec4 texels) each output vec4
// is four consecutive source values, from the source vec4s a and a + 1 shifted by r = (-lowX) mod 4: one
// vec4 fetch per output vec4 (a + 1 is the next column's a) instead of four scalar ones.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool ACTIVATE = false;
layout(constant_id = 4) const bool VEC4_SOURCE = false;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Padded { vec4 xp[]; };
layout(push_constant) uniform Push {
  int depth, height, width;  // D, H, W
  int paddedDepth;           // Dp
  int paddedHeight;          // Hp
  int paddedRowVec4s;        // Wp / 4
  int lowZ, lowY, lowX;      // padding before the first element
  float slope;               // negative slope of f (ACTIVATE)
};

vec4 activated(vec4 v) { return ACTIVATE ? mix(slope * v, v, greaterThan(v, vec4(0.0))) : v; }

// Source vec4 a of the row starting at vec4 `row_start`, 0 outside the row or where the row is padding.
vec4 source_vec4(bool inside, int row_start, int a) {
  if (inside && a >= 0 && a < width / 4) return texelFetch(src, row_start + a);
  return vec4(0.0);
}

// Four consecutive values starting at component r of a, continuing into b.
vec4 shifted(vec4 a, vec4 b, int r) {
  return r == 0 ? a : r == 1 ? vec4(a.yzw, b.x) : r == 2 ? vec4(a.zw, b.xy) : vec4(a.w, b.xyz);
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
  if (VEC4_SOURCE) {
    // Output column j reads source values 4j - lowX + i = 4 (j - k) + r + i, k = (lowX + r) / 4.
    const int r = (-lowX) & 3, k = (lowX + r) / 4, row_start = source / 4;
    vec4 current = source_vec4(inside, row_start, -k);
    for (int column = 0; column < paddedRowVec4s; ++column) {
      const vec4 next = source_vec4(inside, row_start, column + 1 - k);
      xp[row + column] = activated(shifted(current, next, r));
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
    xp[row + column] = activated(v);
  }
}
