#version 450
// Weight packing for the direct convolution (taps reordered, channels last, padded):
//   wp[c, r, s, t, k] = w[k*strideK + c*strideC + (first.x + r*step.x)*strideR
//                         + (first.y + s*step.y)*strideS + (first.z + t*step.z)]    for k < K, else 0
// c packed input channel, k packed output channel, (r, s, t) < taps. The strides say which weight
// axis is which (conv: k = out channel; backward-input: k = in channel) and the steps flip or
// sub-sample the taps (backward-input and transposed conv phases). One invocation writes the vec4 of
// four consecutive k at every tap (r, s, t) of one c. Grid: x = k / 4, y = c (a workgroup per tap and
// channel cost more in workgroup overhead than the copy itself).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer w;
layout(std430, binding = 1) writeonly buffer Packed { vec4 wp[]; };
layout(push_constant) uniform Push {
  ivec4 taps;     // KD, KH, KW of the packed kernel; w unused
  ivec4 first;    // source tap of packed tap 0 along z, y, x; K
  ivec4 step;     // source tap step along z, y, x; Kpad / 4
  ivec4 strides;  // strideK, strideC, strideR, strideS (strideT = 1)
};

void main() {
  const int kVec4 = int(gl_GlobalInvocationID.x);
  if (kVec4 >= step.w) return;
  const int c = int(gl_WorkGroupID.y);
  const int tapCount = taps.x * taps.y * taps.z;
  for (int tap = 0; tap < tapCount; ++tap) {
    const int t = tap % taps.z;
    const int s = (tap / taps.z) % taps.y;
    const int r = tap / (taps.z * taps.y);
    const int source = c * strides.y + (first.x + r * step.x) * strides.z + (first.y + s * step.y) * strides.w +
                       first.z + t * step.z;
    vec4 v = vec4(0.0);
    for (int lane = 0; lane < 4; ++lane) {
      const int k = kVec4 * 4 + lane;
      if (k < first.w) v[lane] = texelFetch(w, source + k * strides.x).x;
    }
    wp[(c * tapCount + tap) * step.w + kVec4] = v;
  }
}
