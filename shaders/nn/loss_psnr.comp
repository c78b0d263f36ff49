#version 450
// PSNR of each sample from its mean squared error, and the losses built on it:
//   P(m) = 10 log10(range^2 / (m + eps)),   dP/dm = -10 / (ln 10 * (m + eps)).
// x, z: per-sample MSEs [N] (x of the image differentiated, z of the other one in a gap).
// MODE (constant_id 3):
//   0  y[0] = (1/N) sum_n P(x_n)                                  (PSNR, mean over samples)
//   1  y[0] = (1/N) sum_n (P(x_n) - P(z_n))^2                     (PSNR gap)
//   2  y[n] = (1/N) dP/dm(x_n) * 2/L                              (PSNR gradient coefficient)
//   3  y[n] = (2/N) (P(x_n) - P(z_n)) dP/dm(x_n) * 2/L            (gap gradient coefficient)
// where L is the number of elements per sample, so that d/da_i = y[n] (a_i - b_i) for i in sample n.
// Modes 0, 1: one invocation; modes 2, 3: one per sample.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MODE = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer z;
layout(std430, binding = 2) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push { uint N; float L; float range; float eps; };

const float kTenOverLn10 = 4.3429448190325175;  // 10 / ln 10

float psnr(float mse) { return kTenOverLn10 * (log(range * range) - log(mse + eps)); }
float slope(float mse) { return -kTenOverLn10 / (mse + eps); }

void main() {
  const uint n = gl_GlobalInvocationID.x;
  if (MODE <= 1) {
    if (n > 0u) return;
    float sum = 0.0;
    for (uint s = 0u; s < N; ++s) {
      const float value = psnr(texelFetch(x, int(s)).x);
      const float gap = value - psnr(texelFetch(z, int(s)).x);
      sum += MODE == 0 ? value : gap * gap;
    }
    y[0] = sum / float(N);
    return;
  }
  if (n >= N) return;
  const float mse = texelFetch(x, int(n)).x;
  const float perElement = 2.0 / L;
  if (MODE == 2) {
    y[n] = slope(mse) * perElement / float(N);
  } else {
    const float gap = psnr(mse) - psnr(texelFetch(z, int(n)).x);
    y[n] = 2.0 * gap * slope(mse) * perElement / float(N);
  }
}
