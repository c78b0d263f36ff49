#version 450
// Resampling of N,C,(D,)H,W by an integer factor k along every spatial axis, PyTorch's
// F.interpolate(scale_factor = k or 1/k, align_corners=False). Separable: along one axis
// y[o] = (1 - w) x[i0] + w x[i1], the source stencil of output index o (n = input size):
//   nearest   up:   i0 = i1 = o / k                 down:  i0 = i1 = o k
//   linear    up:   s = max((o + 1/2) / k - 1/2, 0)  down:  s = (o + 1/2) k - 1/2
//                   i0 = floor(s), i1 = min(i0 + 1, n - 1), w = s - i0
// s is formed exactly as the integer ratio num / den (up: (2o + 1 - k) / 2k, down: ((2o + 1) k - 1) / 2).
// In 2D the depth axis is copied (i0 = i1 = o, w = 0).
//   forward:   y[o] = sum over the 2^dims corners c of  prod_axes weight_c  x[corner c of o]
//              (nearest: the single corner (i0, i0, i0))
//   backward:  gx[i] = sum over outputs o whose stencil touches i of  prod_axes weight(o, i)  gy[o]
//              (a gather: per axis only outputs in candidates(i) can touch input i)
// MODE (constant_id 3): 0 nearest, 1 linear. DOWN (4): 0 up, 1 down. FACTOR (5): k >= 1.
// DIMS (6): 2 or 3. BACKWARD (7): 0 or 1.
// Bindings: source (float texels: x forward, gy backward), out (y forward, gx backward).
// Grid: invocation x, y = x, y of the tensor written; workgroup z strides over its layers (plane, z).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 1;
layout(constant_id = 4) const int DOWN = 0;
layout(constant_id = 5) const int FACTOR = 2;
layout(constant_id = 6) const int DIMS = 3;
layout(constant_id = 7) const int BACKWARD = 0;

layout(binding = 0) uniform samplerBuffer source;
layout(std430, binding = 1) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push {
  ivec3 inSize;   // (W, H, D) of x
  int layers;     // planes (N*C) times the depth of the tensor written
  ivec3 outSize;  // (W, H, D) of y
};

struct Stencil {
  int i0;
  int i1;
  float w;  // weight of i1; i0 gets 1 - w
};

Stencil stencil(int o, int n, bool scaled) {
  if (!scaled) return Stencil(o, o, 0.0);
  if (MODE == 0) {
    const int i = DOWN != 0 ? o * FACTOR : o / FACTOR;
    return Stencil(i, i, 0.0);
  }
  const int den = DOWN != 0 ? 2 : 2 * FACTOR;
  const int num = DOWN != 0 ? (2 * o + 1) * FACTOR - 1 : max(2 * o + 1 - FACTOR, 0);
  const int i0 = num / den;
  return Stencil(i0, min(i0 + 1, n - 1), float(num - i0 * den) / float(den));
}

// The weight output o gives input i along one axis.
float weight(int o, int i, int n, bool scaled) {
  const Stencil s = stencil(o, n, scaled);
  return (s.i0 == i ? 1.0 - s.w : 0.0) + (s.i1 == i ? s.w : 0.0);
}

// Outputs [lo, hi) along one axis that may touch input i (a superset; weight() decides).
ivec2 candidates(int i, int outN, bool scaled) {
  ivec2 range;
  if (!scaled) range = ivec2(i, i + 1);
  else if (MODE == 0 && DOWN != 0) range = ivec2(i / FACTOR, i % FACTOR == 0 ? i / FACTOR + 1 : 0);
  else if (MODE == 0) range = ivec2(i * FACTOR, (i + 1) * FACTOR);
  else if (DOWN != 0) range = ivec2(i / FACTOR - 1, i / FACTOR + 1);
  else range = ivec2(FACTOR * i - (FACTOR + 1) / 2, FACTOR * (i + 1) + (FACTOR + 1) / 2);
  return clamp(range, 0, outN);
}

float forwardValue(int plane, ivec3 o) {
  const Stencil sx = stencil(o.x, inSize.x, true);
  const Stencil sy = stencil(o.y, inSize.y, true);
  const Stencil sz = stencil(o.z, inSize.z, DIMS == 3);
  const int base = plane * inSize.z;
  float value = 0.0;
  for (int c = 0; c < (MODE == 0 ? 1 : DIMS == 3 ? 8 : 4); ++c) {
    const bvec3 upper = bvec3(c & 1, c & 2, c & 4);
    const float w = (upper.x ? sx.w : 1.0 - sx.w) * (upper.y ? sy.w : 1.0 - sy.w) * (upper.z ? sz.w : 1.0 - sz.w);
    const ivec3 i = ivec3(upper.x ? sx.i1 : sx.i0, upper.y ? sy.i1 : sy.i0, upper.z ? sz.i1 : sz.i0);
    value += w * texelFetch(source, ((base + i.z) * inSize.y + i.y) * inSize.x + i.x).r;
  }
  return value;
}

float backwardValue(int plane, ivec3 i) {
  const ivec2 rx = candidates(i.x, outSize.x, true);
  const ivec2 ry = candidates(i.y, outSize.y, true);
  const ivec2 rz = candidates(i.z, outSize.z, DIMS == 3);
  float value = 0.0;
  for (int oz = rz.x; oz < rz.y; ++oz) {
    const float wz = weight(oz, i.z, inSize.z, DIMS == 3);
    for (int oy = ry.x; oy < ry.y; ++oy) {
      const float wzy = wz * weight(oy, i.y, inSize.y, true);
      const int row = ((plane * outSize.z + oz) * outSize.y + oy) * outSize.x;
      for (int ox = rx.x; ox < rx.y; ++ox) {
        const float w = wzy * weight(ox, i.x, inSize.x, true);
        if (w != 0.0) value += w * texelFetch(source, row + ox).r;
      }
    }
  }
  return value;
}

void main() {
  const ivec3 written = BACKWARD != 0 ? inSize : outSize;
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= written.x || p.y >= written.y) return;
  for (int layer = int(gl_WorkGroupID.z); layer < layers; layer += int(gl_NumWorkGroups.z)) {
    const int plane = layer / written.z;
    const ivec3 position = ivec3(p, layer - plane * written.z);
    const float value = BACKWARD != 0 ? backwardValue(plane, position) : forwardValue(plane, position);
    result[(layer * written.y + p.y) * written.x + p.x] = value;
  }
}
