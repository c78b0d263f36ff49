#version 450
#extension GL_GOOGLE_include_directive : require
// Gradient of a loss with respect to its first input, elementwise:
//   grad[i] = scale * g * c[i / segment] * F(a[i], b[i]),
// g = upstream gradient of the scalar loss (one element), c = per-segment coefficients (HAS_COEF,
// constant_id 4; else 1), F = a - b (FORM 0), sign(a - b) (FORM 1, 0 at a = b) or 1 (FORM 2; a, b unused).
// Four items per invocation; a and b are read as vec4 texels.
#include "index.glsl"
#include "broadcast_index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int FORM = 0;
layout(constant_id = 4) const bool HAS_COEF = false;

layout(binding = 0) uniform samplerBuffer upstream;
layout(binding = 1) uniform samplerBuffer coefficients;
layout(binding = 2) uniform samplerBuffer a4;
layout(binding = 3) uniform samplerBuffer b4;
layout(std430, binding = 4) writeonly buffer Output { vec4 grad[]; };
layout(push_constant) uniform Push { uint n; uint segment; uvec2 bySegment; float scale; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  vec4 value = vec4(scale * texelFetch(upstream, 0).x);
  if (HAS_COEF) {
    // Segment of item 4i + l: one division, then at most one step per item when segments hold >= 4.
    const uint first = 4u * item;
    const uint q = divide(first, bySegment);
    const uint r = first - q * segment;
    for (uint l = 0u; l < 4u; ++l) {
      const uint s = segment >= 4u ? q + uint(r + l >= segment) : divide(first + l, bySegment);
      value[l] *= texelFetch(coefficients, int(s)).x;
    }
  }
  if (FORM == 0) value *= texelFetch(a4, int(item)) - texelFetch(b4, int(item));
  if (FORM == 1) value *= sign(texelFetch(a4, int(item)) - texelFetch(b4, int(item)));
  grad[item] = value;
}
