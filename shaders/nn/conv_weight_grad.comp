#version 450
// Weight gradient of the convolution, first stage (partial sums over chunks of output rows):
//   partial[j, k, c, r, s, t] = sum_{m in chunk j} sum_{ox}
//                                 gT[m, ox, k] * xp[n, c, oz*STRIDE + r, oy*STRIDE + s, ox*STRIDE + t]
// m = (n, oz, oy) a row of the output gradient, chunk j = rows [j*rowsPerChunk, (j+1)*rowsPerChunk);
// gT is the output gradient packed by conv_pack_grad as [N*Do*Ho, Wpad, Kpad] (zero past Wo and K),
// xp the padded input [N, C, Dp, Hp, Wp] of the forward pass; (r, s, t) < (KD, KH, KW) the taps.
//
// Blocking: one invocation owns one (c, r) and 4*CHANNEL_VEC4S channels k, i.e. KH*KW*4*CHANNEL_VEC4S
// accumulators. For each PIXELS consecutive ox it fetches KH*SPAN input values (as vec4s when
// ALIGNED_ROWS) and PIXELS*CHANNEL_VEC4S gradient vec4s, and does KH*KW*PIXELS*4*CHANNEL_VEC4S
// multiply-adds, each accumulator its PIXELS in one run (one trip through memory per fetch batch where
// the accumulators spill, as on lavapipe). Lanes run along (c, r); workgroup y is the channel block, z the chunk. Channels
// k >= K are not written.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int KD = 1;
layout(constant_id = 4) const int KH = 3;
layout(constant_id = 5) const int KW = 3;
layout(constant_id = 6) const int STRIDE = 1;
layout(constant_id = 7) const int PIXELS = 8;
layout(constant_id = 8) const int CHANNEL_VEC4S = 1;
layout(constant_id = 9) const bool ALIGNED_ROWS = false;

const int SPAN = (PIXELS - 1) * STRIDE + KW;
const int SPAN_VEC4S = (SPAN + 3) / 4;

layout(binding = 0) uniform samplerBuffer xp;
layout(binding = 1) uniform samplerBuffer xp4;
layout(binding = 2) uniform samplerBuffer gT;
layout(std430, binding = 3) writeonly buffer Partials { float partial[]; };
layout(push_constant) uniform Push {
  int channels;      // C
  int inPlane;       // Dp*Hp*Wp
  int inSlice;       // Hp*Wp
  int inRow;         // Wp
  int outHeight;     // Ho
  int rowsPerItem;   // Do*Ho
  int rows;          // N*Do*Ho
  int rowsPerChunk;
  int xBlocks;       // Wpad / PIXELS
  int gradRow;       // Kpad / 4: vec4s per position of gT
  int outChannels;   // K
};

void main() {
  const int item = int(gl_GlobalInvocationID.x);
  const int c = item / KD;
  const int r = item - c * KD;
  if (c >= channels) return;
  const int kBlock = int(gl_WorkGroupID.y);
  const int chunk = int(gl_WorkGroupID.z);

  vec4 acc[KH][KW][CHANNEL_VEC4S];
  for (int s = 0; s < KH; ++s)
    for (int t = 0; t < KW; ++t)
      for (int q = 0; q < CHANNEL_VEC4S; ++q) acc[s][t][q] = vec4(0.0);

  const int firstRow = chunk * rowsPerChunk;
  const int lastRow = min(firstRow + rowsPerChunk, rows);
  for (int m = firstRow; m < lastRow; ++m) {
    const int n = m / rowsPerItem;
    const int rowInItem = m - n * rowsPerItem;
    const int oz = rowInItem / outHeight;
    const int oy = rowInItem - oz * outHeight;
    int source = (n * channels + c) * inPlane + (oz * STRIDE + r) * inSlice + oy * STRIDE * inRow;
    int g = m * xBlocks * PIXELS * gradRow + kBlock * CHANNEL_VEC4S;
    for (int xBlock = 0; xBlock < xBlocks; ++xBlock, source += PIXELS * STRIDE, g += PIXELS * gradRow) {
      vec4 v[KH][SPAN_VEC4S];
      for (int s = 0; s < KH; ++s) {
        for (int i = 0; i < SPAN_VEC4S; ++i) {
          const int at = source + s * inRow + 4 * i;
          if (ALIGNED_ROWS) {
            v[s][i] = texelFetch(xp4, at / 4);
          } else {
            v[s][i] = vec4(texelFetch(xp, at).x, texelFetch(xp, at + 1).x, texelFetch(xp, at + 2).x,
                           texelFetch(xp, at + 3).x);
          }
        }
      }
      vec4 grad[PIXELS][CHANNEL_VEC4S];
      for (int p = 0; p < PIXELS; ++p)
        for (int q = 0; q < CHANNEL_VEC4S; ++q) grad[p][q] = texelFetch(gT, g + p * gradRow + q);
      for (int s = 0; s < KH; ++s)
        for (int t = 0; t < KW; ++t)
          for (int q = 0; q < CHANNEL_VEC4S; ++q) {
            vec4 sum = acc[s][t][q];
            for (int p = 0; p < PIXELS; ++p) sum += v[s][(p * STRIDE + t) / 4][(p * STRIDE + t) % 4] * grad[p][q];
            acc[s][t][q] = sum;
          }
    }
  }

  const int taps = KD * KH * KW;
  for (int q = 0; q < CHANNEL_VEC4S; ++q) {
    for (int lane = 0; lane < 4; ++lane) {
      const int k = (kBlock * CHANNEL_VEC4S + q) * 4 + lane;
      const int base = ((chunk * outChannels + k) * channels + c) * taps + r * KH * KW;
      for (int s = 0; s < KH; ++s)
        for (int t = 0; t < KW; ++t)
          if (k < outChannels) partial[base + s * KW + t] = acc[s][t][q][lane];
    }
  }
}
