#version 450
// Pointwise (1x1, stride 1, no padding) convolution with packed weights: conv forward of a 1^d kernel and
// its backward-input pass (nets/ops/conv.cpp, docs/convolution.md):
//
//   y[n, k, p] = a[n, k, p] + gate(n, k, p) * (bias[k] + sum_{c<C} wp[c, k] * f(x[n, c, p]))      p < P
//
// p the flattened positions; a the addend, a tensor of y's shape when ADDEND (a residual connection added
// as the output is written), else 0.
// f(v) = v > 0 ? v : inputSlope v when INPUT_ACTIVATION (the forward pass of a convolution that reads its
// input through leaky ReLU), else v; gate(n, k, p) = u[n, k, p] > 0 ? 1 : gateSlope when GATE (the
// backward-input pass of such a convolution: the leaky ReLU's derivative at its forward input u), else 1.
// n batch, c input channel, k output channel. x [N, C, P] and y [N, K, P] are read and written as vec4s
// of four consecutive positions (P is a multiple of 4), so neither needs a padded copy; wp holds the
// weights as [C, Kpad] (weightRow = Kpad / 4 vec4s per input channel), read as vec4s: either packed, Kpad a
// multiple of 4*ceil(CHANNELS/4) and zero past K, or the backward-input pass's own weight tensor [K', C'] read
// in place (Kpad = K = C', a multiple of 4); a block's weight vec4s past K are not fetched.
//
// Blocking: one invocation computes POSITION_VEC4S vec4s of positions for CHANNELS output channels. Per
// input channel it fetches POSITION_VEC4S input vec4s and ceil(CHANNELS/4) weight vec4s and does
// CHANNELS*POSITION_VEC4S vec4 multiply-adds. It fetches INPUT_GROUP input channels before their
// multiply-adds, each accumulator then taking INPUT_GROUP in one run (the same sums in the same order);
// the channels past the last whole group go one by one. Lanes run along the position blocks (workgroup y);
// workgroup x is the channel block, so the blocks of one tile run back to back and find its inputs in
// cache; workgroup z is the batch item. Channels k >= K and positions past P are not written.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int POSITION_VEC4S = 4;
layout(constant_id = 4) const int CHANNELS = 8;
layout(constant_id = 5) const bool HAS_BIAS = false;
layout(constant_id = 6) const bool INPUT_ACTIVATION = false;
layout(constant_id = 7) const bool GATE = false;
layout(constant_id = 8) const bool ADDEND = false;
layout(constant_id = 9) const int INPUT_GROUP = 1;

const int CHANNEL_VEC4S = (CHANNELS + 3) / 4;

layout(binding = 0) uniform samplerBuffer x4;
layout(binding = 1) uniform samplerBuffer wp;
layout(binding = 2) uniform samplerBuffer bias;
layout(binding = 3) uniform samplerBuffer gate4;  // [N, K, P] as vec4s, read when GATE
layout(binding = 4) uniform samplerBuffer addend4;  // [N, K, P] as vec4s, read when ADDEND
layout(std430, binding = 5) writeonly buffer Output { vec4 y4[]; };
layout(push_constant) uniform Push {
  int channels;     // C
  int planeVec4s;   // P / 4
  int outChannels;  // K
  int weightRow;    // Kpad / 4: vec4s per input channel of wp
  float inputSlope;
  float gateSlope;
};

// f(x) at vec4 index i of x.
vec4 inputAt(int i) {
  const vec4 v = texelFetch(x4, i);
  return INPUT_ACTIVATION ? mix(inputSlope * v, v, greaterThan(v, vec4(0.0))) : v;
}

// Weight vec4 q of the block from output channel k0 in the row from vec4 w; zero past the output channels.
vec4 weightAt(int w, int k0, int q) { return k0 + 4 * q < outChannels ? texelFetch(wp, w + q) : vec4(0.0); }

void main() {
  const int first = int(gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x) * POSITION_VEC4S;
  if (first >= planeVec4s) return;
  const int k0 = int(gl_WorkGroupID.x) * CHANNELS;
  const int n = int(gl_WorkGroupID.z);
  // The last block reads its first vec4 again where it would pass the plane; those are not written.
  int at[POSITION_VEC4S];
  for (int v = 0; v < POSITION_VEC4S; ++v) at[v] = min(first + v, planeVec4s - 1);

  vec4 acc[CHANNELS][POSITION_VEC4S];
  for (int q = 0; q < CHANNEL_VEC4S; ++q) {
    const vec4 b = HAS_BIAS ? texelFetch(bias, k0 / 4 + q) : vec4(0.0);
    for (int lane = 0; lane < 4; ++lane)
      if (q * 4 + lane < CHANNELS)
        for (int v = 0; v < POSITION_VEC4S; ++v) acc[q * 4 + lane][v] = vec4(b[lane]);
  }

  int source = n * channels * planeVec4s;
  int w = k0 / 4;
  int c = 0;
  for (; c + INPUT_GROUP <= channels; c += INPUT_GROUP, source += INPUT_GROUP * planeVec4s, w += INPUT_GROUP * weightRow) {
    vec4 xv[INPUT_GROUP][POSITION_VEC4S];
    vec4 weight[INPUT_GROUP][CHANNEL_VEC4S];
    for (int g = 0; g < INPUT_GROUP; ++g) {
      for (int v = 0; v < POSITION_VEC4S; ++v) xv[g][v] = inputAt(source + g * planeVec4s + at[v]);
      for (int q = 0; q < CHANNEL_VEC4S; ++q) weight[g][q] = weightAt(w + g * weightRow, k0, q);
    }
    for (int k = 0; k < CHANNELS; ++k)
      for (int v = 0; v < POSITION_VEC4S; ++v) {
        vec4 sum = acc[k][v];
        for (int g = 0; g < INPUT_GROUP; ++g) sum += weight[g][k / 4][k % 4] * xv[g][v];
        acc[k][v] = sum;
      }
  }
  for (; c < channels; ++c, source += planeVec4s, w += weightRow) {
    vec4 xv[POSITION_VEC4S];
    for (int v = 0; v < POSITION_VEC4S; ++v) xv[v] = inputAt(source + at[v]);
    vec4 weight[CHANNEL_VEC4S];
    for (int q = 0; q < CHANNEL_VEC4S; ++q) weight[q] = weightAt(w, k0, q);
    for (int k = 0; k < CHANNELS; ++k)
      for (int v = 0; v < POSITION_VEC4S; ++v) acc[k][v] += weight[k / 4][k % 4] * xv[v];
  }

  const int outBase = (n * outChannels + k0) * planeVec4s;
  for (int k = 0; k < CHANNELS; ++k) {
    if (k0 + k >= outChannels) break;
    for (int v = 0; v < POSITION_VEC4S; ++v) {
      if (first + v >= planeVec4s) continue;
      const int index = outBase + k * planeVec4s + first + v;
      vec4 value = acc[k][v];
      if (GATE) value = mix(gateSlope * value, value, greaterThan(texelFetch(gate4, index), vec4(0.0)));
      if (ADDEND) value = texelFetch(addend4, index) + value;
      y4[index] = value;
    }
  }
}
