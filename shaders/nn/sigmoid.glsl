// Sigmoid s = 1 / (1 + e^-x) and its complement 1 - s = s(-x), both from e = exp(-|x|) so neither
// overflows nor loses relative precision in the tails: s = 1 / (1 + e) for x >= 0, e / (1 + e) below.
// SiLU f = x s and its derivative f' = s (1 + x (1 - s)) from them (shared by nn/activation and the
// GroupNorm kernels that apply SiLU after the normalisation, so both give the same bits).
vec4 sigmoid(vec4 x, out vec4 complement) {
  const vec4 e = exp(-abs(x));
  const vec4 near = 1.0 / (1.0 + e);
  const vec4 far = e * near;
  const bvec4 positive = greaterThanEqual(x, vec4(0.0));
  complement = mix(near, far, positive);
  return mix(far, near, positive);
}

vec4 silu(vec4 x) {
  vec4 unused;
  return x * sigmoid(x, unused);
}

// gy f'(x) for f = SiLU
vec4 siluBackward(vec4 x, vec4 gy) {
  vec4 complement;
  const vec4 s = sigmoid(x, complement);
  return gy * s * (1.0 + x * complement);
}
