#version 450
#extension GL_KHR_shader_subgroup_arithmetic : require
// Bias gradient of the convolution (and of its transposed form):
//
//   partial[j, k] = sum_n sum_{p in chunk} g[n, k, p]      slot j = chunk * S + s,   db[k] = sum_j partial[j, k]
//
// g [N, K, P] the output gradient, read as vec4s of four consecutive positions when VEC4S (P a multiple
// of 4), as floats otherwise; a unit is one such read. A workgroup sums one chunk of the plane for one
// channel k over every batch item; its lanes interleave (lane l takes units l, l + W, l + 2W, ... of the
// chunk, W the workgroup size), so one fetch of the lanes reads neighbouring memory, and each subgroup s
// of the S in the workgroup adds its lanes with subgroupAdd. With one slot (one chunk, one subgroup)
// partial is db itself; otherwise conv_sum_partials adds the slots. Workgroup x is the chunk, y the channel.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool VEC4S = false;

layout(binding = 0) uniform samplerBuffer g;
layout(binding = 1) uniform samplerBuffer g4;
layout(std430, binding = 2) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push {
  int channels;    // K
  int batch;       // N
  int planeUnits;  // P / 4 when VEC4S, else P
  int chunkUnits;  // units per chunk, a multiple of the workgroup size
};

void main() {
  const int chunk = int(gl_WorkGroupID.x);
  const int k = int(gl_WorkGroupID.y);
  const int step = int(gl_WorkGroupSize.x);
  const int end = min((chunk + 1) * chunkUnits, planeUnits);
  vec4 sum = vec4(0.0);
  for (int n = 0; n < batch; ++n) {
    const int base = (n * channels + k) * planeUnits;
    for (int u = chunk * chunkUnits + int(gl_LocalInvocationID.x); u < end; u += step)
      sum += VEC4S ? texelFetch(g4, base + u) : vec4(texelFetch(g, base + u).x, 0.0, 0.0, 0.0);
  }
  const float total = subgroupAdd(dot(sum, vec4(1.0)));
  const int slot = chunk * int(gl_NumSubgroups) + int(gl_SubgroupID);
  if (subgroupElect()) partial[slot * channels + k] = total;
}
