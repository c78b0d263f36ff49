#version 450
// Weight packing of a convolution's own weight in its own tap order, as a transpose of 4 x 4 blocks:
//   wp[r, k] = w[k, r]   for k < K, else 0        r = c taps + tap < R = C taps,  k < Kpad
// the layout conv_pack_weights writes (wp[c, tap, k]) for a weight w [K, C, taps] read as K rows of R values.
// With R a multiple of 4 every row is whole vec4 texels: one invocation fetches the vec4 at column block j of
// four rows k0..k0+3 (zero for rows past K) and writes their columns as four vec4s of wp, four fetches for
// sixteen values where the general packing makes sixteen scalar ones. Lanes run along j (neighbouring
// texels of each row); workgroup y is the block of rows k0 / 4.
// Bindings: w (vec4 texels), wp (storage, vec4s).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer w4;
layout(std430, binding = 1) writeonly buffer Packed { vec4 wp[]; };
layout(push_constant) uniform Push {
  int rowVec4s;    // R / 4
  int rows;        // K
  int paddedRow;   // Kpad / 4: vec4s per packed column r
};

void main() {
  const int j = int(gl_GlobalInvocationID.x);
  if (j >= rowVec4s) return;
  const int kBlock = int(gl_WorkGroupID.y);
  vec4 block[4];
  for (int i = 0; i < 4; ++i) {
    const int k = 4 * kBlock + i;
    block[i] = k < rows ? texelFetch(w4, k * rowVec4s + j) : vec4(0.0);
  }
  for (int column = 0; column < 4; ++column)
    wp[(4 * j + column) * paddedRow + kBlock] =
        vec4(block[0][column], block[1][column], block[2][column], block[3][column]);
}
