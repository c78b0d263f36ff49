#version 450
// GroupNorm backward, pass 1 of 3: per chunk of a plane p = n C + c (S contiguous elements of x, gy),
//   partial[p][chunk] = (sum gy, sum gy xhat),   xhat = (x - mean_b) rstd_b,  b = the group of p.
// Workgroup (chunk, p) covers elements [chunk L, min((chunk + 1) L, S)) of plane p, L = CHUNK.
// VEC4 (constant_id 3): 1 when S % 4 == 0, then x and gy are read as vec4 texels. CHUNK (constant_id 4).
// Bindings: x, gy (texels), stats (float texels, (mean, rstd) per group), partial (storage).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;
layout(constant_id = 4) const int CHUNK = 4096;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(binding = 2) uniform samplerBuffer stats;
layout(std430, binding = 3) writeonly buffer Partial { vec2 partial[]; };
layout(push_constant) uniform Push { int planeSize; int chunks; int channelsPerGroup; };

shared vec2 tree[gl_WorkGroupSize.x];

void main() {
  const int chunk = int(gl_WorkGroupID.x);
  const int plane = int(gl_WorkGroupID.y);
  const int block = plane / channelsPerGroup;
  const float mean = texelFetch(stats, 2 * block).r;
  const float rstd = texelFetch(stats, 2 * block + 1).r;
  const int begin = plane * planeSize + chunk * CHUNK;
  const int end = plane * planeSize + min((chunk + 1) * CHUNK, planeSize);
  const int local = int(gl_LocalInvocationID.x);
  const int stride = int(gl_WorkGroupSize.x);

  vec2 sum = vec2(0.0);
  if (VEC4 != 0) {
    for (int t = begin / 4 + local; t < end / 4; t += stride) {
      const vec4 g = texelFetch(gy, t);
      sum += vec2((g.x + g.y) + (g.z + g.w), dot(g, (texelFetch(x, t) - mean) * rstd));
    }
  } else {
    for (int i = begin + local; i < end; i += stride) {
      const float g = texelFetch(gy, i).r;
      sum += vec2(g, g * (texelFetch(x, i).r - mean) * rstd);
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
