#version 450
#extension GL_GOOGLE_include_directive : require
// Sum over chosen axes of a mapped input:
//   y[o] = scale * sum_{r1 < R1, r0 < R0} MAP(a[i], b[i]),  i = (((k2*R1 + r1)*K1 + k1)*R0 + r0)*K0 + k0,
//   o = (k2*K1 + k1)*K0 + k0.
// The host collapses the input to [K2, R1, K1, R0, K0] (K kept, R reduced). MAP (constant_id 3) is
// a (0), a - b (1), (a - b)^2 (2), |a - b| (3) or a^2 (4); b has a's shape and is unused by 0 and 4.
// With P = partials > 1 the reduced positions r = r1*R0 + r0 are cut into chunks of CHUNK and
// invocation (o, p) writes the partial sum of chunk p to y[p*O + o]; a second pass sums the partials.
// VEC4 (constant_id 4): K0 = 1 and R0, CHUNK multiples of 4, so a and b are read as vec4 texels.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int MAP = 0;
layout(constant_id = 4) const bool VEC4 = false;

layout(binding = 0) uniform samplerBuffer a;
layout(binding = 1) uniform samplerBuffer b;
layout(std430, binding = 2) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push { uint K2, R1, K1, R0, K0, chunk, partials; float scale; };

float map1(float x, float z) {
  if (MAP == 1) return x - z;
  if (MAP == 2) return (x - z) * (x - z);
  if (MAP == 3) return abs(x - z);
  if (MAP == 4) return x * x;
  return x;
}

vec4 map4(vec4 x, vec4 z) {
  if (MAP == 1) return x - z;
  if (MAP == 2) return (x - z) * (x - z);
  if (MAP == 3) return abs(x - z);
  if (MAP == 4) return x * x;
  return x;
}

bool readsB() { return MAP == 1 || MAP == 2 || MAP == 3; }

float sumRun(uint base, uint first, uint last, uint k0) {
  float sum = 0.0;
  if (VEC4) {
    for (uint r0 = first; r0 < last; r0 += 4u) {
      const int texel = int((base + r0) / 4u);
      const vec4 value = map4(texelFetch(a, texel), readsB() ? texelFetch(b, texel) : vec4(0.0));
      sum += (value.x + value.y) + (value.z + value.w);
    }
  } else {
    for (uint r0 = first; r0 < last; ++r0) {
      const int index = int((base + r0) * K0 + k0);
      sum += map1(texelFetch(a, index).x, readsB() ? texelFetch(b, index).x : 0.0);
    }
  }
  return sum;
}

void main() {
  const uint outputs = K2 * K1 * K0;
  const uint item = flat_index();
  if (item >= outputs * partials) return;
  const uint o = item % outputs;
  const uint p = item / outputs;
  const uint k0 = o % K0;
  const uint k1 = (o / K0) % K1;
  const uint k2 = o / (K0 * K1);

  const uint begin = p * chunk;
  const uint end = min(begin + chunk, R1 * R0);
  uint r1 = begin / R0;
  uint r0 = begin - r1 * R0;
  float sum = 0.0;
  for (uint position = begin; position < end; ++r1) {
    const uint last = min(R0, r0 + (end - position));
    // (k2, r1, k1, 0, k0) is at base * K0 + k0.
    const uint base = ((k2 * R1 + r1) * K1 + k1) * R0;
    sum += sumRun(base, r0, last, k0);
    position += last - r0;
    r0 = 0u;
  }
  y[item] = scale * sum;
}
