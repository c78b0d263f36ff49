#version 450
#extension GL_GOOGLE_include_directive : require
// GroupNorm backward, pass 2 of 3: sums the chunk partials (A, B) = (sum gy, sum gy xhat) of every plane
// p = n C + c (group_norm_backward_reduce) into
//   channel role, j < C:        gbeta[j] = sum_n A[n, j],   ggamma[j] = sum_n B[n, j]
//   group role,   j < N G:      coef[j] = (sum_{c in j} gamma[c] A[n, c], sum_{c in j} gamma[c] B[n, c]) / M
// (M = (C / G) S) which group_norm_backward_apply turns into gx. Invocation j takes both roles.
// Bindings: partial (float texels, 2 per chunk), gamma (float texels), ggamma, gbeta, coef (storage).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer partial;
layout(binding = 1) uniform samplerBuffer gamma;
layout(std430, binding = 2) writeonly buffer GradGamma { float ggamma[]; };
layout(std430, binding = 3) writeonly buffer GradBeta { float gbeta[]; };
layout(std430, binding = 4) writeonly buffer Coefficients { vec2 coef[]; };
layout(push_constant) uniform Push { int batch; int channels; int groups; int chunks; float invGroupSize; };

// (A, B) of plane p summed over its chunks
vec2 planeSum(int plane) {
  vec2 sum = vec2(0.0);
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int first = 2 * (plane * chunks + chunk);
    sum += vec2(texelFetch(partial, first).r, texelFetch(partial, first + 1).r);
  }
  return sum;
}

void main() {
  const int j = int(flat_index());
  if (j < channels) {
    vec2 sum = vec2(0.0);
    for (int n = 0; n < batch; ++n) sum += planeSum(n * channels + j);
    gbeta[j] = sum.x;
    ggamma[j] = sum.y;
  }
  if (j < batch * groups) {
    const int channelsPerGroup = channels / groups;
    const int firstPlane = j * channelsPerGroup;
    const int firstChannel = firstPlane % channels;
    vec2 sum = vec2(0.0);
    for (int k = 0; k < channelsPerGroup; ++k) sum += texelFetch(gamma, firstChannel + k).r * planeSum(firstPlane + k);
    coef[j] = sum * invGroupSize;
  }
}
