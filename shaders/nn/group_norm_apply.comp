#version 450
#extension GL_GOOGLE_include_directive : require
// GroupNorm, normalisation: z = (x - mean_b) rstd_b gamma[c] + beta[c] for x [N, C, S...], written
// (x - mean) a + beta with a = rstd gamma, never x a + (beta - mean a), which cancels for large means;
// y = z, or y = SiLU(z) = z s(z) when SILU (the norm-then-SiLU of a DDPM residual block in one pass).
// Plane p = n C + c holds S contiguous elements; its group is b = p / (C / G).
// Workgroup (chunk, p) covers elements [chunk L, min((chunk + 1) L, S)) of plane p, L = CHUNK; each
// invocation fetches the plane's parameters once, then strides over the chunk 4 elements at a time.
// VEC4 (constant_id 3) = 1 when S % 4 == 0: x read as vec4 texels, y written as vec4. SILU (constant_id 5).
// Bindings: x (texels), gamma, beta (float texels, [C]), stats (float texels, (mean, rstd) per group),
// y (storage).
#include "sigmoid.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;
layout(constant_id = 4) const int CHUNK = 4096;
layout(constant_id = 5) const int SILU = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gamma;
layout(binding = 2) uniform samplerBuffer beta;
layout(binding = 3) uniform samplerBuffer stats;
layout(std430, binding = 4) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push { int planeSize; int channels; int channelsPerGroup; };

vec4 activated(vec4 z) { return SILU != 0 ? silu(z) : z; }

void main() {
  const int plane = int(gl_WorkGroupID.y);
  const int block = plane / channelsPerGroup;
  const int c = plane % channels;
  const float mean = texelFetch(stats, 2 * block).r;
  const float a = texelFetch(stats, 2 * block + 1).r * texelFetch(gamma, c).r;
  const float b = texelFetch(beta, c).r;
  const int chunkEnd = min((int(gl_WorkGroupID.x) + 1) * CHUNK, planeSize);
  const int stride = 4 * int(gl_WorkGroupSize.x);
  for (int first = int(gl_WorkGroupID.x) * CHUNK + 4 * int(gl_LocalInvocationID.x); first < chunkEnd; first += stride) {
    const int i = plane * planeSize + first;
    if (VEC4 != 0) {
      y[i / 4] = activated((texelFetch(x, i / 4) - mean) * a + b);
    } else {
      for (int k = 0; k < 4 && first + k < chunkEnd; ++k)
        y[(i + k) / 4][(i + k) % 4] = activated(vec4((texelFetch(x, i + k).r - mean) * a + b)).x;
    }
  }
}
