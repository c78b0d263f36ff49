#version 450
#extension GL_KHR_shader_subgroup_arithmetic : require
// Weight gradient of the pointwise (1x1, stride 1, no padding) convolution, first stage (partial sums
// over chunks of positions):
//
//   partial[j, k, c] = sum_{p in chunk} g[n, k, p] * f(x[n, c, p])      slot j = (n * chunks + chunk) * S + s
//
// f(v) = v > 0 ? v : slope v when INPUT_ACTIVATION (a convolution that reads its input through leaky
// ReLU), else v.
// g [N, K, P] the output gradient and x [N, C, P] the input, both read as vec4s of four consecutive
// positions (P a multiple of 4), neither copied. A workgroup sums one chunk of chunkVec4s position
// vec4s; its lanes interleave (lane l takes vec4s l, l + W, l + 2W, ... of the chunk, W the workgroup
// size), so the lanes of one fetch read neighbouring memory, and each subgroup s of the S in the
// workgroup adds its lanes' sums with subgroupAdd. conv_sum_partials adds the slots.
//
// Blocking: one invocation owns IN_CHANNELS input and OUT_CHANNELS output channels,
// IN_CHANNELS*OUT_CHANNELS vec4 accumulators. Per position vec4 it fetches IN_CHANNELS + OUT_CHANNELS
// vec4s and does IN_CHANNELS*OUT_CHANNELS vec4 multiply-adds. It fetches STEPS of its position vec4s
// before their multiply-adds, each accumulator then taking STEPS in one run (the same sums in the same
// order); a tail of fewer goes one by one. Workgroup x is the chunk, y the
// channel-block pair (input block fastest), z the batch item. Channels past C or K read channel C-1 or
// K-1 again and are not written.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int IN_CHANNELS = 4;
layout(constant_id = 4) const int OUT_CHANNELS = 4;
layout(constant_id = 5) const bool INPUT_ACTIVATION = false;
layout(constant_id = 6) const int STEPS = 1;

layout(binding = 0) uniform samplerBuffer x4;
layout(binding = 1) uniform samplerBuffer g4;
layout(std430, binding = 2) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push {
  int channels;     // C
  int outChannels;  // K
  int planeVec4s;   // P / 4
  int chunkVec4s;   // position vec4s per chunk, a multiple of the workgroup size
  int inBlocks;     // ceil(C / IN_CHANNELS)
  float slope;      // negative slope of f
};

// f(x) at vec4 index i of x.
vec4 inputAt(int i) {
  const vec4 v = texelFetch(x4, i);
  return INPUT_ACTIVATION ? mix(slope * v, v, greaterThan(v, vec4(0.0))) : v;
}

void main() {
  const int chunk = int(gl_WorkGroupID.x);
  const int pair = int(gl_WorkGroupID.y);
  const int c0 = (pair % inBlocks) * IN_CHANNELS;
  const int k0 = (pair / inBlocks) * OUT_CHANNELS;
  const int n = int(gl_WorkGroupID.z);
  int xRow[IN_CHANNELS];
  for (int i = 0; i < IN_CHANNELS; ++i) xRow[i] = (n * channels + min(c0 + i, channels - 1)) * planeVec4s;
  int gRow[OUT_CHANNELS];
  for (int o = 0; o < OUT_CHANNELS; ++o) gRow[o] = (n * outChannels + min(k0 + o, outChannels - 1)) * planeVec4s;

  vec4 acc[IN_CHANNELS][OUT_CHANNELS];
  for (int i = 0; i < IN_CHANNELS; ++i)
    for (int o = 0; o < OUT_CHANNELS; ++o) acc[i][o] = vec4(0.0);

  const int step = int(gl_WorkGroupSize.x);
  const int end = min((chunk + 1) * chunkVec4s, planeVec4s);
  int p = chunk * chunkVec4s + int(gl_LocalInvocationID.x);
  for (; p + (STEPS - 1) * step < end; p += STEPS * step) {
    vec4 xv[STEPS][IN_CHANNELS];
    vec4 gv[STEPS][OUT_CHANNELS];
    for (int u = 0; u < STEPS; ++u) {
      for (int i = 0; i < IN_CHANNELS; ++i) xv[u][i] = inputAt(xRow[i] + p + u * step);
      for (int o = 0; o < OUT_CHANNELS; ++o) gv[u][o] = texelFetch(g4, gRow[o] + p + u * step);
    }
    for (int i = 0; i < IN_CHANNELS; ++i)
      for (int o = 0; o < OUT_CHANNELS; ++o) {
        vec4 sum = acc[i][o];
        for (int u = 0; u < STEPS; ++u) sum += xv[u][i] * gv[u][o];
        acc[i][o] = sum;
      }
  }
  for (; p < end; p += step) {
    vec4 xv[IN_CHANNELS];
    for (int i = 0; i < IN_CHANNELS; ++i) xv[i] = inputAt(xRow[i] + p);
    vec4 gv[OUT_CHANNELS];
    for (int o = 0; o < OUT_CHANNELS; ++o) gv[o] = texelFetch(g4, gRow[o] + p);
    for (int i = 0; i < IN_CHANNELS; ++i)
      for (int o = 0; o < OUT_CHANNELS; ++o) acc[i][o] += xv[i] * gv[o];
  }

  const int slot = (n * int(gl_NumWorkGroups.x) + chunk) * int(gl_NumSubgroups) + int(gl_SubgroupID);
  for (int o = 0; o < OUT_CHANNELS; ++o) {
    for (int i = 0; i < IN_CHANNELS; ++i) {
      const float total = subgroupAdd(dot(acc[i][o], vec4(1.0)));
      if (subgroupElect() && k0 + o < outChannels && c0 + i < channels)
        partial[(slot * outChannels + k0 + o) * channels + c0 + i] = total;
    }
  }
}
