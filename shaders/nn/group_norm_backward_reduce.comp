#version 450
#extension GL_GOOGLE_include_directive : require
// GroupNorm backward, pass 1 of 3: per chunk of a plane p = n C + c (S contiguous elements of x, gy),
//   partial[p][chunk] = (sum gz, sum gz xhat),   xhat = (x - mean_b) rstd_b,  b = the group of p,
// gz the gradient at the normalised output z = xhat gamma[c] + beta[c]: gz = gy, or with SILU (the
// output was y = SiLU(z)) gz = gy SiLU'(z), z recomputed as group_norm_apply computes it.
// Workgroup (chunk, p) covers elements [chunk L, min((chunk + 1) L, S)) of plane p, L = CHUNK.
// VEC4 (constant_id 3): 1 when S % 4 == 0, then x and gy are read as vec4 texels. CHUNK (constant_id 4).
// SILU (constant_id 5).
// Bindings: x, gy (texels), stats (float texels, (mean, rstd) per group), gamma, beta (float texels, [C],
// read only with SILU), partial (storage).
#include "group_norm_silu_gradient.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;
layout(constant_id = 4) const int CHUNK = 4096;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(binding = 2) uniform samplerBuffer stats;
layout(binding = 3) uniform samplerBuffer gamma;
layout(binding = 4) uniform samplerBuffer beta;
layout(std430, binding = 5) writeonly buffer Partial { vec2 partial[]; };
layout(push_constant) uniform Push { int planeSize; int chunks; int channelsPerGroup; int channels; };

shared vec2 tree[gl_WorkGroupSize.x];

void main() {
  const int chunk = int(gl_WorkGroupID.x);
  const int plane = int(gl_WorkGroupID.y);
  const int block = plane / channelsPerGroup;
  const int c = plane % channels;
  const float mean = texelFetch(stats, 2 * block).r;
  const float rstd = texelFetch(stats, 2 * block + 1).r;
  const NormOutput norm = NormOutput(mean, rstd * texelFetch(gamma, c).r, texelFetch(beta, c).r);
  const int begin = plane * planeSize + chunk * CHUNK;
  const int end = plane * planeSize + min((chunk + 1) * CHUNK, planeSize);
  const int local = int(gl_LocalInvocationID.x);
  const int stride = int(gl_WorkGroupSize.x);

  vec2 sum = vec2(0.0);
  if (VEC4 != 0) {
    for (int t = begin / 4 + local; t < end / 4; t += stride) {
      const vec4 xt = texelFetch(x, t);
      const vec4 g = normOutputGradient(norm, xt, texelFetch(gy, t));
      sum += vec2((g.x + g.y) + (g.z + g.w), dot(g, (xt - mean) * rstd));
    }
  } else {
    for (int i = begin + local; i < end; i += stride) {
      const float xi = texelFetch(x, i).r;
      const float g = normOutputGradient(norm, vec4(xi), vec4(texelFetch(gy, i).r)).x;
      sum += vec2(g, g * (xi - mean) * rstd);
    }
  }

  tree[local] = sum;
  barrier();
  for (int half_ = stride / 2; half_ > 0; half_ /= 2) {
    if (local < half_) tree[local] += tree[local + half_];
    barrier();
  }
  if (local == 0) partial[plane * chunks + chunk] = tree[0];
}
