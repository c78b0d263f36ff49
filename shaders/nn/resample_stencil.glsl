// Resampling along one axis by an integer factor k, PyTorch's F.interpolate(align_corners=False):
//   y[o] = (1 - w) x[i0] + w x[i1]   with the source stencil of output o (n = input size):
//   nearest   up:   i0 = i1 = o / k                  down:  i0 = i1 = o k
//   linear    up:   s = max((o + 1/2) / k - 1/2, 0)   down:  s = (o + 1/2) k - 1/2
//                   i0 = floor(s), i1 = min(i0 + 1, n - 1), w = s - i0
// s is formed exactly as an integer ratio (up: (2o + 1 - k) / 2k, down: ((2o + 1) k - 1) / 2).
// The including shader defines the specialization constants MODE (0 nearest, 1 linear), DOWN (0 up,
// 1 down) and FACTOR (k).
#ifndef SMOKESVD_RESAMPLE_STENCIL_GLSL
#define SMOKESVD_RESAMPLE_STENCIL_GLSL

struct Stencil {
  int i0;
  int i1;
  float w;  // weight of i1; i0 gets 1 - w
};

Stencil stencil(int o, int n) {
  if (MODE == 0) {
    const int i = DOWN != 0 ? o * FACTOR : o / FACTOR;
    return Stencil(i, i, 0.0);
  }
  const int den = DOWN != 0 ? 2 : 2 * FACTOR;
  const int num = DOWN != 0 ? (2 * o + 1) * FACTOR - 1 : max(2 * o + 1 - FACTOR, 0);
  const int i0 = num / den;
  return Stencil(i0, min(i0 + 1, n - 1), float(num - i0 * den) / float(den));
}

// The weight output o gives input i (the transpose of the stencil).
float weight(int o, int i, int n) {
  const Stencil s = stencil(o, n);
  return (s.i0 == i ? 1.0 - s.w : 0.0) + (s.i1 == i ? s.w : 0.0);
}

// Outputs [lo, hi) that may touch input i among m outputs (a superset; weight() decides).
ivec2 candidates(int i, int m) {
  ivec2 range;
  if (MODE == 0 && DOWN != 0) range = ivec2(i / FACTOR, i % FACTOR == 0 ? i / FACTOR + 1 : 0);
  else if (MODE == 0) range = ivec2(i * FACTOR, (i + 1) * FACTOR);
  else if (DOWN != 0) range = ivec2(i / FACTOR - 1, i / FACTOR + 1);
  else range = ivec2(FACTOR * i - (FACTOR + 1) / 2, FACTOR * (i + 1) + (FACTOR + 1) / 2);
  return clamp(range, 0, m);
}

#endif
