#version 450
// GroupNorm statistics, pass 1 of 2: per chunk of a group, its mean and sum of squared deviations.
// Group b = n G + g of x [N, C, S...] is the contiguous block of M = (C / G) S elements at b M.
// Workgroup (chunk, b) reduces elements [chunk L, min((chunk + 1) L, M)) of block b, L = CHUNK:
//   mean_c = p + sum (x - p) / count        (p = the chunk's first element, a shift that keeps the sum
//                                            small for inputs with a large mean, e.g. 1000 +- 1)
//   m2_c   = sum (x - mean_c)^2              (second pass over the chunk, which is in cache)
// and writes partial[b][chunk] = (mean_c, m2_c). group_norm_finalize merges the chunks (Chan et al.).
// With FINAL (a group of one chunk) it writes what the merge of that one chunk gives instead, the group's
// statistics stats[b] = (mean, 1 / sqrt(m2 / M + eps)), and no finalize pass runs.
// VEC4 (constant_id 3): 1 when M % 4 == 0, then x is read as vec4 texels. CHUNK (constant_id 4).
// Bindings: x (texels), partial or stats (storage, 2 floats per chunk or group).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;
layout(constant_id = 4) const int CHUNK = 4096;
layout(constant_id = 5) const bool FINAL = false;

layout(binding = 0) uniform samplerBuffer x;
layout(std430, binding = 1) writeonly buffer Partial { vec2 partial[]; };
layout(push_constant) uniform Push { int groupSize; int chunks; float eps; };

shared float tree[gl_WorkGroupSize.x];

// sum over this invocation's share of [begin, end) of (x - shift) (or its square); begin, end % 4 == 0 in VEC4
float localSum(int begin, int end, float shift, bool squares) {
  const int local = int(gl_LocalInvocationID.x);
  const int stride = int(gl_WorkGroupSize.x);
  float sum = 0.0;
  if (VEC4 != 0) {
    for (int t = begin / 4 + local; t < end / 4; t += stride) {
      const vec4 d = texelFetch(x, t) - shift;
      sum += squares ? dot(d, d) : (d.x + d.y) + (d.z + d.w);
    }
  } else {
    for (int i = begin + local; i < end; i += stride) {
      const float d = texelFetch(x, i).r - shift;
      sum += squares ? d * d : d;
    }
  }
  return sum;
}

float workgroupSum(float value) {
  const uint local = gl_LocalInvocationID.x;
  barrier();
  tree[local] = value;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) tree[local] += tree[local + half_];
    barrier();
  }
  return tree[0];
}

void main() {
  const int chunk = int(gl_WorkGroupID.x);
  const int block = int(gl_WorkGroupID.y);
  const int begin = block * groupSize + chunk * CHUNK;
  const int end = block * groupSize + min((chunk + 1) * CHUNK, groupSize);
  const float count = float(end - begin);
  const float pivot = texelFetch(x, VEC4 != 0 ? begin / 4 : begin).x;
  const float mean = pivot + workgroupSum(localSum(begin, end, pivot, false)) / count;
  const float m2 = workgroupSum(localSum(begin, end, mean, true));
  if (gl_LocalInvocationID.x != 0u) return;
  if (FINAL) {
    // group_norm_finalize's merge of this one chunk into an empty one (n, mean, m2 = 0), operation for
    // operation, so that the statistics are the same bits: mean' = 0 + d c / c, m2' = 0 + m2 + d^2 0 c / c.
    const float d = mean - 0.0;
    const float merged = 0.0 + d * count / count;
    partial[block] = vec2(merged, 1.0 / sqrt((0.0 + m2 + d * d * 0.0 * count / count) / float(groupSize) + eps));
    return;
  }
  partial[block * chunks + chunk] = vec2(mean, m2);
}
