#version 450
// Weight packing of a stride-1 convolution's backward-input pass (its transposed convolution), from vec4 blocks:
//   wp[c, t, k] = w[c, k, TAPS - 1 - t]   for k < K, else 0        c < C, t < TAPS, k < Kpad
// the layout conv_pack_weights writes for that pass: w [C, K, taps] is the convolution's weight [Cout, Cin, taps]
// (packed input channel c = Cout, packed output channel k = Cin) with its taps flipped along every axis, which
// reverses their flat order. With K a multiple of 4 the taps of four consecutive k are 4 TAPS consecutive values
// from a vec4 boundary: one invocation fetches them as TAPS vec4s and writes each tap's four k as one vec4,
// TAPS fetches where the general packing makes 4 TAPS scalar ones. Lanes run along the block of k; workgroup
// y is c.
// Bindings: w (vec4 texels), wp (storage, vec4s).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int TAPS = 9;

layout(binding = 0) uniform samplerBuffer w4;
layout(std430, binding = 1) writeonly buffer Packed { vec4 wp[]; };
layout(push_constant) uniform Push {
  int channels;   // K
  int paddedRow;  // Kpad / 4
};

void main() {
  const int kBlock = int(gl_GlobalInvocationID.x);
  if (kBlock >= paddedRow) return;
  const int c = int(gl_WorkGroupID.y);
  vec4 taps[TAPS];  // k = 4 kBlock + i, tap t at flat position i TAPS + t
  const bool inside = 4 * kBlock < channels;
  const int first = (c * channels + 4 * kBlock) * TAPS / 4;
  for (int v = 0; v < TAPS; ++v) taps[v] = inside ? texelFetch(w4, first + v) : vec4(0.0);
  for (int t = 0; t < TAPS; ++t) {
    vec4 packed;
    for (int i = 0; i < 4; ++i) {
      const int at = i * TAPS + (TAPS - 1 - t);
      packed[i] = taps[at / 4][at % 4];
    }
    wp[(c * TAPS + t) * paddedRow + kBlock] = packed;
  }
}
