#version 450
#extension GL_GOOGLE_include_directive : require
// GroupNorm statistics, pass 2 of 2: merges the chunk partials of group b (group_norm_stats) with the
// pairwise update of Chan et al., which adds no cancellation:
//   n = na + nb,  d = mean_b - mean_a,  mean = mean_a + d nb / n,  m2 = m2_a + m2_b + d^2 na nb / n
// then stats[b] = (mean, rstd), rstd = 1 / sqrt(m2 / M + eps)  (biased variance, as PyTorch).
// Bindings: partial (float texels, 2 per chunk), stats (storage, 2 floats per group).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int CHUNK = 4096;

layout(binding = 0) uniform samplerBuffer partial;
layout(std430, binding = 1) writeonly buffer Stats { vec2 stats[]; };
layout(push_constant) uniform Push { int groupSize; int chunks; int blocks; float eps; };

void main() {
  const int block = int(flat_index());
  if (block >= blocks) return;
  float n = 0.0, mean = 0.0, m2 = 0.0;
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int first = (block * chunks + chunk) * 2;
    const float chunkMean = texelFetch(partial, first).r;
    const float chunkM2 = texelFetch(partial, first + 1).r;
    const float chunkN = float(min(CHUNK, groupSize - chunk * CHUNK));
    const float total = n + chunkN;
    const float d = chunkMean - mean;
    mean += d * chunkN / total;
    m2 += chunkM2 + d * d * n * chunkN / total;
    n = total;
  }
  stats[block] = vec2(mean, 1.0 / sqrt(m2 / float(groupSize) + eps));
}
