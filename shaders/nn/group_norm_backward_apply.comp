#version 450
#extension GL_GOOGLE_include_directive : require
// GroupNorm backward, pass 3 of 3: the input gradient
//   gx = rstd_b (gamma[c] gz - m1_b - xhat m2_b),   xhat = (x - mean_b) rstd_b,
// with (m1, m2) = coef[b] the group means of gamma gz and gamma gz xhat (group_norm_backward_finalize),
// gz = gy, or with SILU gy SiLU'(z) (group_norm_silu_gradient.glsl).
// Plane p = n C + c holds S contiguous elements; its group is b = p / (C / G).
// Workgroup (chunk, p) covers elements [chunk L, min((chunk + 1) L, S)) of plane p, L = CHUNK; each
// invocation fetches the plane's parameters once, then strides over the chunk 4 elements at a time.
// VEC4 (constant_id 3) = 1 when S % 4 == 0: x, gy read as vec4 texels, gx written as vec4. SILU (constant_id 5).
// Bindings: x, gy (texels), gamma, beta (float texels; beta read only with SILU), stats ((mean, rstd) per
// group), coef ((m1, m2) per group), gx (storage).
#include "group_norm_silu_gradient.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;
layout(constant_id = 4) const int CHUNK = 4096;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(binding = 2) uniform samplerBuffer gamma;
layout(binding = 3) uniform samplerBuffer beta;
layout(binding = 4) uniform samplerBuffer stats;
layout(binding = 5) uniform samplerBuffer coef;
layout(std430, binding = 6) writeonly buffer Output { vec4 gx[]; };
layout(push_constant) uniform Push { int planeSize; int channels; int channelsPerGroup; };

void main() {
  const int plane = int(gl_WorkGroupID.y);
  const int block = plane / channelsPerGroup;
  const int c = plane % channels;
  const float g = texelFetch(gamma, c).r;
  const float mean = texelFetch(stats, 2 * block).r;
  const float rstd = texelFetch(stats, 2 * block + 1).r;
  const float m1 = texelFetch(coef, 2 * block).r;
  const float m2 = texelFetch(coef, 2 * block + 1).r;
  const NormOutput norm = NormOutput(mean, rstd * g, texelFetch(beta, c).r);
  const int chunkEnd = min((int(gl_WorkGroupID.x) + 1) * CHUNK, planeSize);
  const int stride = 4 * int(gl_WorkGroupSize.x);
  for (int first = int(gl_WorkGroupID.x) * CHUNK + 4 * int(gl_LocalInvocationID.x); first < chunkEnd; first += stride) {
    const int i = plane * planeSize + first;
    if (VEC4 != 0) {
      const vec4 xt = texelFetch(x, i / 4);
      gx[i / 4] = rstd * (g * normOutputGradient(norm, xt, texelFetch(gy, i / 4)) - m1 - (xt - mean) * rstd * m2);
    } else {
      for (int k = 0; k < 4 && first + k < chunkEnd; ++k) {
        const float xk = texelFetch(x, i + k).r;
        const float xhat = (xk - mean) * rstd;
        const float gz = normOutputGradient(norm, vec4(xk), vec4(texelFetch(gy, i + k).r)).x;
        gx[(i + k) / 4][(i + k) % 4] = rstd * (g * gz - m1 - xhat * m2);
      }
    }
  }
}
