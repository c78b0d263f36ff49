#version 450
// Advances an optimiser's step counter and writes the scalars of that step, all on the GPU, so a
// recorded training step can be submitted again and again with nothing written or read by the host.
//
// state[0] = t, the number of steps taken including this one (a float: exact up to 2^24 steps)
// s = t - 1, the steps taken before this one; W = warmup, S = s - W (steps after the warm-up)
//   lr(s) = base * (s + 1) / W                                    when s < W (linear warm-up)
//         = base                                                  KIND 0, constant
//         = base * gamma^floor(S / step_size)                     KIND 1, step decay
//         = min_lr + (base - min_lr) (1 + cos(pi min(S, T) / T))/2 KIND 2, cosine over T = cosine_steps
// state[1] = lr
// state[5] = c1 = 1 - beta1^t, state[6] = c2 = 1 - beta2^t, the bias corrections, computed from t alone as
//   c = -expm1(t ln beta)
// with ln beta passed from double and expm1 by its Taylor series where 1 - exp would cancel. In float,
// 1 - pow(beta, t) would be off by about 1e-5 relative for beta = 0.999 (rounding beta alone), and a
// running recurrence would stall short of 1.
// state[2] = lr / c1                         (Adam's step size with the first-moment bias correction)
// state[3] = sqrt(c2)                        (the second-moment bias correction, as a square root)
// state[4] = 1 - lr * decoupled_decay        (AdamW's multiplicative weight decay; 1 for Adam)
// One invocation runs (workgroup 1x1x1).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int KIND = 0;

layout(std430, binding = 0) buffer State { float state[]; };
layout(push_constant) uniform Push {
  float base_lr;
  float log_beta1;
  float log_beta2;
  float decoupled_decay;
  float warmup;
  float step_size;
  float gamma;
  float cosine_steps;
  float min_lr;
};

float scheduled_lr(float s) {
  if (s < warmup) return base_lr * (s + 1.0) / warmup;
  const float after = s - warmup;
  if (KIND == 1) return base_lr * pow(gamma, floor(after / step_size));
  if (KIND == 2) {
    const float progress = min(after, cosine_steps) / cosine_steps;
    return min_lr + (base_lr - min_lr) * 0.5 * (1.0 + cos(3.14159265358979 * progress));
  }
  return base_lr;
}

// 1 - e^x for x <= 0 without cancellation: the Taylor series of -expm1 near 0 (11 terms: below float
// rounding for |x| <= 1/2), 1 - exp(x) further out.
float one_minus_exp(float x) {
  if (x < -0.5) return 1.0 - exp(x);
  float series = 1.0;
  for (int n = 11; n >= 2; --n) series = 1.0 + x / float(n) * series;
  return -x * series;
}

void main() {
  const float t = state[0] + 1.0;
  const float lr = scheduled_lr(t - 1.0);
  const float c1 = one_minus_exp(t * log_beta1);
  const float c2 = one_minus_exp(t * log_beta2);
  state[0] = t;
  state[1] = lr;
  state[2] = lr / c1;
  state[3] = sqrt(c2);
  state[4] = 1.0 - lr * decoupled_decay;
  state[5] = c1;
  state[6] = c2;
}
