#version 450
#extension GL_GOOGLE_include_directive : require
// One pass of a two-pass reduction: partial[g] = scale * REDUCE(x[i]) over the items this workgroup g
// visits (grid-stride over vec4 texels, then a tree in shared memory). REDUCE is sum (constant_id 3 = 0)
// or max (= 1). Pass 1 runs G workgroups over x; pass 2 runs one workgroup over the G partials, with
// scale = 1/n for a mean.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int REDUCE_MAX = 0;

layout(binding = 0) uniform samplerBuffer x4;
layout(std430, binding = 1) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push { uint n; float scale; };

shared float tree[gl_WorkGroupSize.x];

float identity() { return REDUCE_MAX != 0 ? -uintBitsToFloat(0x7f800000u) : 0.0; }
float combine(float a, float b) { return REDUCE_MAX != 0 ? max(a, b) : a + b; }

void main() {
  const uint local = gl_LocalInvocationID.x;
  const uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  const uint texels = (n + 3u) / 4u;
  float accumulator = identity();
  for (uint t = gl_GlobalInvocationID.x; t < texels; t += stride) {
    const vec4 v = texelFetch(x4, int(t));
    const uint base = 4u * t;
    if (base + 3u < n) {
      accumulator = combine(accumulator, combine(combine(v.x, v.y), combine(v.z, v.w)));
    } else {
      for (uint lane = 0u; base + lane < n; ++lane) accumulator = combine(accumulator, v[lane]);
    }
  }
  tree[local] = accumulator;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) tree[local] = combine(tree[local], tree[local + half_]);
    barrier();
  }
  if (local == 0u) partial[gl_WorkGroupID.x] = tree[0] * scale;
}
