#version 450
// Direct convolution over a zero-padded input with packed weights: the one kernel behind conv forward,
// conv backward-input and transposed conv (nets/ops/conv.cpp, docs/convolution.md).
//
//   y[n, k, Z, Y, X] = a[n, k, Z, Y, X] + gate(n, k, Z, Y, X) * (bias[k] + sum_{c<C} sum_{r<KD, s<KH, t<KW}
//                        wp[c, r, s, t, k] * xp[n, c, oz*STRIDE + r, oy*STRIDE + s, ox*STRIDE + t])
//   (Z, Y, X) = (oz*outStepZ, oy*outStepY, ox*outStepX) + outBase,   (oz, oy, ox) < (gridD, gridH, gridW)
//   gate = u[n, k, Z, Y, X] > 0 ? 1 : gateSlope when GATE, else 1: the backward-input pass of a convolution
//   that reads its input u through leaky ReLU (u has y's shape), multiplied by the activation's derivative;
//   a = the addend, a tensor of y's shape when ADDEND (a residual connection added as y is written), else 0.
//
// n batch, c input channel, k output channel, (r, s, t) tap, (oz, oy, ox) grid position. xp is the
// padded input [N, C, Dp, Hp, Wp] read from element inBase on; wp holds the taps as
// [C, KD, KH, KW, Kpad] with Kpad a multiple of 4*CHANNEL_VEC4S, zero past K, read as vec4s.
// A strided grid (outStep > 1) writes one phase of a transposed convolution.
//
// Blocking: one invocation computes PIXELS consecutive ox of one grid row for 4*CHANNEL_VEC4S output
// channels. Per input channel and (r, s) it fetches the SPAN input values the row of taps touches (as
// vec4s when the rows start on a vec4, ALIGNED_ROWS) and reuses each for up to KW taps and all its
// channels; each weight vec4 serves PIXELS outputs. Every inner loop has a constant trip count and
// indexes a local array of that length by its counter, so it is unrolled and the arrays become registers.
// Fetch order: by kernel row (default), each (r, s) row's inputs and taps are fetched and multiplied
// before the next row's; with PER_INPUT_CHANNEL, all KD*KH rows and all taps of an input channel are
// fetched first and then each accumulator takes all of the channel's multiply-adds in one run. The sums
// are the same, in the same order. On lavapipe every fetch is a call that spills the accumulators, so
// the second order moves each accumulator through memory once per input channel instead of once per
// kernel row (docs/convolution.md); on a GPU the first keeps fewer values live.
// Lanes run along the flattened (x block, oy, oz), workgroup y; workgroup x is the channel block, so the
// blocks of one tile run one after another and find its inputs in cache; workgroup z is the batch item.
// Positions ox >= gridW and channels k >= K are computed but not written.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int KD = 1;
layout(constant_id = 4) const int KH = 3;
layout(constant_id = 5) const int KW = 3;
layout(constant_id = 6) const int STRIDE = 1;
layout(constant_id = 7) const int PIXELS = 8;
layout(constant_id = 8) const int CHANNEL_VEC4S = 2;
layout(constant_id = 9) const bool HAS_BIAS = false;
layout(constant_id = 10) const bool ALIGNED_ROWS = false;
layout(constant_id = 11) const bool GATE = false;
layout(constant_id = 12) const bool ADDEND = false;
layout(constant_id = 13) const bool PER_INPUT_CHANNEL = false;

const int SPAN = (PIXELS - 1) * STRIDE + KW;
const int SPAN_VEC4S = (SPAN + 3) / 4;
const int ROWS = KD * KH;  // kernel rows (r, s) per input channel
const int ROW_SLOTS = ROWS > 0 ? ROWS : 1;  // a phase with no taps (KD = 0) keeps its arrays non-empty

layout(binding = 0) uniform samplerBuffer xp;
layout(binding = 1) uniform samplerBuffer xp4;
layout(binding = 2) uniform samplerBuffer wp;
layout(binding = 3) uniform samplerBuffer bias;
layout(binding = 4) uniform samplerBuffer gate;  // u, read when GATE
layout(binding = 5) uniform samplerBuffer addend;  // read when ADDEND
layout(std430, binding = 6) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push {
  int channels;     // C
  int inPlane;      // Dp*Hp*Wp
  int inSlice;      // Hp*Wp
  int inRow;        // Wp
  int inBase;
  int gridD;
  int gridH;
  int gridW;
  int xBlocks;      // ceil(gridW / PIXELS)
  int outChannels;  // K
  int weightRow;    // Kpad / 4: vec4s per tap
  int outPlane;     // elements of one output channel
  int outStepZ;
  int outStepY;
  int outStepX;
  int outBase;
  float gateSlope;
};

// Input values rowStart + 4i .. rowStart + 4i + 3.
vec4 inputVec4(int rowStart, int i) {
  if (ALIGNED_ROWS) return texelFetch(xp4, rowStart / 4 + i);
  const int at = rowStart + 4 * i;
  return vec4(texelFetch(xp, at).x, texelFetch(xp, at + 1).x, texelFetch(xp, at + 2).x, texelFetch(xp, at + 3).x);
}

void main() {
  const int item = int(gl_WorkGroupID.y * gl_WorkGroupSize.x + gl_LocalInvocationID.x);
  const int xBlock = item % xBlocks;
  const int gridRow = item / xBlocks;
  const int oy = gridRow % gridH;
  const int oz = gridRow / gridH;
  if (oz >= gridD) return;
  const int kBlock = int(gl_WorkGroupID.x);
  const int n = int(gl_WorkGroupID.z);
  const int ox0 = xBlock * PIXELS;

  vec4 acc[PIXELS][CHANNEL_VEC4S];
  for (int q = 0; q < CHANNEL_VEC4S; ++q) {
    const vec4 b = HAS_BIAS ? texelFetch(bias, kBlock * CHANNEL_VEC4S + q) : vec4(0.0);
    for (int p = 0; p < PIXELS; ++p) acc[p][q] = b;
  }

  const int tapsPerChannel = KD * KH * KW * weightRow;
  int source = inBase + n * channels * inPlane + oz * STRIDE * inSlice + oy * STRIDE * inRow + ox0 * STRIDE;
  int w = kBlock * CHANNEL_VEC4S;
  for (int c = 0; c < channels; ++c, source += inPlane, w += tapsPerChannel) {
    if (PER_INPUT_CHANNEL) {
      vec4 v[ROW_SLOTS][SPAN_VEC4S];
      for (int row = 0; row < ROWS; ++row)
        for (int i = 0; i < SPAN_VEC4S; ++i) v[row][i] = inputVec4(source + (row / KH) * inSlice + (row % KH) * inRow, i);
      vec4 weight[ROW_SLOTS * KW][CHANNEL_VEC4S];
      for (int tap = 0; tap < ROWS * KW; ++tap)
        for (int q = 0; q < CHANNEL_VEC4S; ++q) weight[tap][q] = texelFetch(wp, w + tap * weightRow + q);
      for (int p = 0; p < PIXELS; ++p)
        for (int q = 0; q < CHANNEL_VEC4S; ++q) {
          vec4 sum = acc[p][q];
          for (int row = 0; row < ROWS; ++row)
            for (int t = 0; t < KW; ++t) sum += v[row][(p * STRIDE + t) / 4][(p * STRIDE + t) % 4] * weight[row * KW + t][q];
          acc[p][q] = sum;
        }
    } else {
      for (int row = 0; row < ROWS; ++row) {
        vec4 v[SPAN_VEC4S];
        for (int i = 0; i < SPAN_VEC4S; ++i) v[i] = inputVec4(source + (row / KH) * inSlice + (row % KH) * inRow, i);
        vec4 weight[KW][CHANNEL_VEC4S];
        for (int t = 0; t < KW; ++t)
          for (int q = 0; q < CHANNEL_VEC4S; ++q) weight[t][q] = texelFetch(wp, w + (row * KW + t) * weightRow + q);
        for (int p = 0; p < PIXELS; ++p)
          for (int t = 0; t < KW; ++t)
            for (int q = 0; q < CHANNEL_VEC4S; ++q) acc[p][q] += v[(p * STRIDE + t) / 4][(p * STRIDE + t) % 4] * weight[t][q];
      }
    }
  }

  const int outRow = n * outChannels * outPlane + outBase + oz * outStepZ + oy * outStepY;
  for (int p = 0; p < PIXELS; ++p) {
    const int ox = ox0 + p;
    for (int q = 0; q < CHANNEL_VEC4S; ++q) {
      for (int lane = 0; lane < 4; ++lane) {
        const int k = (kBlock * CHANNEL_VEC4S + q) * 4 + lane;
        if (ox >= gridW || k >= outChannels) continue;
        const int index = outRow + k * outPlane + ox * outStepX;
        float value = acc[p][q][lane];
        if (GATE && !(texelFetch(gate, index).x > 0.0)) value = gateSlope * value;
        if (ADDEND) value = texelFetch(addend, index).x + value;
        y[index] = value;
      }
    }
  }
}
