#version 450
// Max or average pooling, kernel 2, stride 2, no padding, ceil mode: windows at the far edge of an odd
// size are clipped to the input. With W(o) the clipped window of output o and |W(o)| its size:
//   forward   max:      y[o] = x[a(o)], a(o) = the first maximum of W(o) in (z, y, x) scan order
//                                       (a NaN wins, as in PyTorch)
//             average:  y[o] = sum_{i in W(o)} x[i] / |W(o)|
//   backward  max:      gx[i] = i == a(o) ? gy[o] : 0      average:  gx[i] = gy[o] / |W(o)|
// Windows are disjoint and cover the input, so a backward invocation writes its whole window.
// MAX (constant_id 3): 0 average, 1 max. DIMS (constant_id 4): 2 or 3 (2D inputs have depth 1).
// BACKWARD (constant_id 5): 0 or 1.
// Bindings: x (float texels; read by max), gy (float texels; read by backward), out (y or gx).
// Grid: invocation x, y = output x, y; workgroup z strides over layers = planes (N*C) x output depth.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MAX = 1;
layout(constant_id = 4) const int DIMS = 2;
layout(constant_id = 5) const int BACKWARD = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(std430, binding = 2) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push {
  ivec3 inSize;   // (W, H, D)
  int layers;
  ivec3 outSize;  // (W, H, D)
};

const int KZ = DIMS == 3 ? 2 : 1;

struct Window {
  int corner;     // flat index of the window's first element
  ivec3 extent;   // clipped size (x, y, z)
};

// The flat input index of the window's element number k in (z, y, x) scan order; -1 past the clip.
int element(Window w, int k) {
  const ivec3 d = ivec3(k & 1, (k >> 1) & 1, k >> 2);
  if (any(greaterThanEqual(d, w.extent))) return -1;
  return w.corner + (d.z * inSize.y + d.y) * inSize.x + d.x;
}

int argmax(Window w) {
  int best = w.corner;
  float bestValue = texelFetch(x, best).r;
  for (int k = 1; k < 4 * KZ; ++k) {
    const int i = element(w, k);
    if (i < 0) continue;
    const float v = texelFetch(x, i).r;
    if (v > bestValue || (isnan(v) && !isnan(bestValue))) {
      bestValue = v;
      best = i;
    }
  }
  return best;
}

void main() {
  const ivec2 o = ivec2(gl_GlobalInvocationID.xy);
  if (o.x >= outSize.x || o.y >= outSize.y) return;
  for (int layer = int(gl_WorkGroupID.z); layer < layers; layer += int(gl_NumWorkGroups.z)) {
    const int plane = layer / outSize.z;
    const ivec3 start = 2 * ivec3(o, layer - plane * outSize.z);
    const Window w = Window(((plane * inSize.z + start.z) * inSize.y + start.y) * inSize.x + start.x,
                            min(start + ivec3(2, 2, KZ), inSize) - start);
    const int outIndex = ((layer * outSize.y) + o.y) * outSize.x + o.x;
    const float count = float(w.extent.x * w.extent.y * w.extent.z);
    const int best = MAX != 0 ? argmax(w) : -1;

    if (BACKWARD == 0) {
      float sum = 0.0;
      for (int k = 0; k < 4 * KZ && MAX == 0; ++k) {
        const int i = element(w, k);
        if (i >= 0) sum += texelFetch(x, i).r;
      }
      result[outIndex] = MAX != 0 ? texelFetch(x, best).r : sum / count;
      continue;
    }
    const float g = texelFetch(gy, outIndex).r;
    for (int k = 0; k < 4 * KZ; ++k) {
      const int i = element(w, k);
      if (i >= 0) result[i] = MAX != 0 ? (i == best ? g : 0.0) : g / count;
    }
  }
}
