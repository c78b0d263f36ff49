// The gradient at GroupNorm's normalised output z = (x - mean) a + b (a = rstd gamma[c], b = beta[c]),
// from the gradient gy of the op's output: gy itself, or with SILU (constant_id 5: the output was
// SiLU(z)) gy SiLU'(z), z recomputed in the same order as group_norm_apply computes it.
#include "sigmoid.glsl"
layout(constant_id = 5) const int SILU = 0;

struct NormOutput {
  float mean, a, b;
};

vec4 normOutputGradient(NormOutput norm, vec4 x, vec4 gy) {
  return SILU != 0 ? siluBackward((x - norm.mean) * norm.a + norm.b, gy) : gy;
}
