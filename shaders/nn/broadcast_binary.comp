#version 450
#extension GL_GOOGLE_include_directive : require
// y[d0, d1, d2, d3] = a[...] OP b[...] with broadcasting, OP in {add, sub, mul, div, copy a}
// (constant_id 3: 0..4). The host collapses the output to [D0, D1, D2, D3] (d3 fastest) so that along
// each collapsed axis each operand is either contiguous or broadcast:
//   a index = d0*sa0 + d1*sa1 + d2*sa2 + d3*A_INNER   (sa* = 0 where a is broadcast), b likewise.
// Invocation i computes the four output elements 4i..4i+3 (one vec4 of y). With VEC4 (constant_id 7,
// D3 % 4 == 0) they share a row and a running operand is one vec4 texel; otherwise each element is
// located on its own. A_FULL / B_FULL (constant_id 5, 6): the operand has y's shape and is read at i.
#include "index.glsl"
#include "broadcast_index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int OP = 0;
layout(constant_id = 4) const int INNER = 3;     // bit 0: a runs along d3, bit 1: b runs along d3
layout(constant_id = 5) const bool A_FULL = false;
layout(constant_id = 6) const bool B_FULL = false;
layout(constant_id = 7) const bool VEC4 = false;

layout(binding = 0) uniform samplerBuffer a;
layout(binding = 1) uniform samplerBuffer b;
layout(std430, binding = 2) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push {
  uint n;                      // elements of y
  uint D1, D2, D3;
  uvec2 byD1, byD2, byD3;      // fast divisors (broadcast_index.glsl)
  uint sa0, sa1, sa2, sb0, sb1, sb2;
};

// Flat index into an operand with strides s and inner flag of output element (d0, d1, d2, d3).
uint operandIndex(uvec4 d, uvec3 s, bool inner) { return d.x * s.x + d.y * s.y + d.z * s.z + (inner ? d.w : 0u); }

uvec4 coordinates(uint element) {
  const uint rows = divide(element, byD3);
  const uint planes = divide(rows, byD2);
  const uint d0 = divide(planes, byD1);
  return uvec4(d0, planes - d0 * D1, rows - planes * D2, element - rows * D3);
}

vec4 operand(samplerBuffer source, bool full, bool inner, uvec3 strides, uint item, uvec4 first) {
  if (full) return texelFetch(source, int(item));
  if (VEC4) {
    const uint base = operandIndex(first, strides, inner);
    return inner ? texelFetch(source, int(base / 4u)) : vec4(texelFetch(source, int(base)).x);
  }
  vec4 values;
  for (uint lane = 0u; lane < 4u; ++lane) {
    const uint element = min(4u * item + lane, n - 1u);  // the last vec4 may run past y's end
    values[lane] = texelFetch(source, int(operandIndex(coordinates(element), strides, inner))).x;
  }
  return values;
}

vec4 apply(vec4 x, vec4 z) {
  if (OP == 0) return x + z;
  if (OP == 1) return x - z;
  if (OP == 2) return x * z;
  if (OP == 3) return x / z;
  return x;
}

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const uvec4 first = coordinates(4u * item);
  const vec4 x = operand(a, A_FULL, (INNER & 1) != 0, uvec3(sa0, sa1, sa2), item, first);
  const vec4 z = OP == 4 ? vec4(0.0) : operand(b, B_FULL, (INNER & 2) != 0, uvec3(sb0, sb1, sb2), item, first);
  y[item] = apply(x, z);
}
