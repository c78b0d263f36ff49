#version 450
#extension GL_GOOGLE_include_directive : require
// Max or average pooling, kernel 2, stride 2, no padding, ceil mode: windows at the far edge of an odd
// size are clipped to the input. With W(o) the clipped window of output o and |W(o)| its size:
//   forward   max:      y[o] = x[a(o)], a(o) = the first maximum of W(o) in (z, y, x) scan order
//                                       (a NaN wins, as in PyTorch)
//             average:  y[o] = sum_{i in W(o)} x[i] / |W(o)|
//   backward  max:      gx[i] = i == a(o) ? gy[o] : 0      average:  gx[i] = gy[o] / |W(o)|
// Windows are disjoint and cover the input, so a backward invocation writes its whole window.
// Each invocation handles SEGMENT quads (4 consecutive outputs along x) of one output row,
// item = (row, segment), row = (plane, oz, oy). With ALIGNED (input width % 8 == 0) a quad's window rows
// are two vec4 texels of x (and of gx); otherwise every element is fetched and stored on its own.
// Specialization constants: MAX (3): 0 average, 1 max. DIMS (4): 2 or 3 (2D inputs have depth 1).
// BACKWARD (5). ALIGNED (6).
// Bindings: x (texels; read by max), gy (texels; read by backward), out (y or gx).
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MAX = 1;
layout(constant_id = 4) const int DIMS = 2;
layout(constant_id = 5) const int BACKWARD = 0;
layout(constant_id = 6) const int ALIGNED = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(std430, binding = 2) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push {
  ivec3 inSize;        // (W, H, D)
  int quadsPerRow;     // ceil(output W / 4)
  ivec3 outSize;       // (W, H, D)
  int segmentsPerRow;  // ceil(quadsPerRow / SEGMENT)
  uint items;          // output rows times segmentsPerRow
};

const int SEGMENT = 4;
const int KZ = DIMS == 3 ? 2 : 1;

// Whether window row r = (dz, dy) = (r / 2, r % 2) exists, and the flat index of its first element.
bool rowInside(ivec3 start, int r) { return start.z + r / 2 < inSize.z && start.y + r % 2 < inSize.y; }
int rowStart(int plane, ivec3 start, int r) {
  return ((plane * inSize.z + start.z + r / 2) * inSize.y + start.y + r % 2) * inSize.x + start.x;
}

// Pooling of one window whose elements are read by the caller in scan order; v replaces the best when
// it is larger, or a NaN where the best is not.
bool better(float v, float best) { return v > best || (isnan(v) && !isnan(best)); }
bvec4 better(vec4 v, vec4 best) {
  return bvec4(better(v.x, best.x), better(v.y, best.y), better(v.z, best.z), better(v.w, best.w));
}

void storeElement(int index, float value) { result[index / 4][index % 4] = value; }

// One output element on the unaligned path: window start (x, y, z), its forward value or its backward.
void elementWindow(int plane, ivec3 start, int outIndex) {
  if (start.x >= inSize.x) return;
  const int width = min(2, inSize.x - start.x);
  float best = 0.0, sum = 0.0, count = 0.0;
  int arg = -1;
  for (int r = 0; r < 2 * KZ; ++r) {
    if (!rowInside(start, r)) continue;
    for (int dx = 0; dx < width; ++dx) {
      const int i = rowStart(plane, start, r) + dx;
      if (MAX != 0) {
        const float v = texelFetch(x, i).r;
        if (arg < 0 || better(v, best)) {
          best = v;
          arg = i;
        }
      }
      count += 1.0;
    }
  }
  if (BACKWARD == 0) {
    if (MAX == 0)
      for (int r = 0; r < 2 * KZ; ++r)
        for (int dx = 0; dx < width && rowInside(start, r); ++dx)
          sum += texelFetch(x, rowStart(plane, start, r) + dx).r;
    storeElement(outIndex, MAX != 0 ? best : sum / count);
    return;
  }
  const float g = texelFetch(gy, outIndex).r;
  for (int r = 0; r < 2 * KZ; ++r)
    for (int dx = 0; dx < width && rowInside(start, r); ++dx) {
      const int i = rowStart(plane, start, r) + dx;
      storeElement(i, MAX != 0 ? (i == arg ? g : 0.0) : g / count);
    }
}

// One quad on the aligned path: window rows are the texel pair (2q, 2q + 1) of 8 input elements, split
// into the quad's left (even) and right (odd) window columns.
void quadWindow(int plane, ivec3 start, int outIndex) {
  vec4 best = vec4(0.0), sum = vec4(0.0);
  ivec4 arg = ivec4(-1);  // 2 r + dx of the window's maximum
  float count = 0.0;
  for (int r = 0; r < 2 * KZ; ++r) {
    if (!rowInside(start, r)) continue;
    const int texel = rowStart(plane, start, r) / 4;
    const vec4 a = texelFetch(x, texel), b = texelFetch(x, texel + 1);
    const vec4 left = vec4(a.xz, b.xz), right = vec4(a.yw, b.yw);
    count += 2.0;
    if (MAX == 0) {
      sum += left + right;
      continue;
    }
    const bvec4 rightWins = better(right, left);
    const vec4 rowBest = mix(left, right, rightWins);
    const bvec4 replace = count == 2.0 ? bvec4(true) : better(rowBest, best);
    best = mix(best, rowBest, replace);
    arg = mix(arg, 2 * r + ivec4(rightWins), replace);
  }
  if (BACKWARD == 0) {
    result[outIndex / 4] = MAX != 0 ? best : sum / count;
    return;
  }
  const vec4 g = texelFetch(gy, outIndex / 4);
  for (int r = 0; r < 2 * KZ; ++r) {
    if (!rowInside(start, r)) continue;
    const vec4 left = MAX != 0 ? mix(vec4(0.0), g, equal(arg, ivec4(2 * r))) : g / count;
    const vec4 right = MAX != 0 ? mix(vec4(0.0), g, equal(arg, ivec4(2 * r + 1))) : g / count;
    const int texel = rowStart(plane, start, r) / 4;
    result[texel] = vec4(left.x, right.x, left.y, right.y);
    result[texel + 1] = vec4(left.z, right.z, left.w, right.w);
  }
}

void main() {
  const uint item = flat_index();
  if (item >= items) return;
  const int row = int(item) / segmentsPerRow;
  const int firstQuad = SEGMENT * (int(item) - row * segmentsPerRow);
  const int endQuad = min(firstQuad + SEGMENT, quadsPerRow);
  const int layer = row / outSize.y;  // plane outSize.z + oz
  const int oy = row - layer * outSize.y;
  const int plane = layer / outSize.z;
  const int oz = layer - plane * outSize.z;
  for (int q = firstQuad; q < endQuad; ++q) {
    const int outIndex = row * outSize.x + 4 * q;
    const ivec3 start = 2 * ivec3(4 * q, oy, oz);
    if (ALIGNED != 0) {
      quadWindow(plane, start, outIndex);
    } else {
      for (int t = 0; t < 4 && 4 * q + t < outSize.x; ++t)
        elementWindow(plane, start + ivec3(2 * t, 0, 0), outIndex + t);
    }
  }
}
