#version 450
// Output gradient in rows with channels last, for the weight gradient:
//   gT[m, x, k] = g[n, k, m - n*rowsPerItem, x]   for x < W and k < K, else 0
// m = (n, z, y) a row of g [N, K, D, H, W] (rowsPerItem = D*H); gT is [N*D*H, Wpad, Kpad], Kpad a
// multiple of 4. One invocation writes the Kpad channels of one x; lanes run along x, workgroup y is m.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer g;
layout(std430, binding = 1) writeonly buffer Packed { vec4 gT[]; };
layout(push_constant) uniform Push {
  int channels;      // K
  int rowsPerItem;   // D*H
  int width;         // W
  int paddedWidth;   // Wpad
  int channelVec4s;  // Kpad / 4
};

void main() {
  const int x = int(gl_GlobalInvocationID.x);
  if (x >= paddedWidth) return;
  const int m = int(gl_WorkGroupID.y);
  const int n = m / rowsPerItem;
  const int plane = rowsPerItem * width;
  const int source = n * channels * plane + (m - n * rowsPerItem) * width + x;
  const int target = (m * paddedWidth + x) * channelVec4s;
  for (int kVec4 = 0; kVec4 < channelVec4s; ++kVec4) {
    vec4 v = vec4(0.0);
    for (int lane = 0; lane < 4; ++lane) {
      const int k = kVec4 * 4 + lane;
      if (x < width && k < channels) v[lane] = texelFetch(g, source + k * plane).x;
    }
    gT[target + kVec4] = v;
  }
}
