#version 450
// y[d0, d1, d2, d3] = a[...] OP b[...] with broadcasting, OP in {add, sub, mul, div, copy a}
// (constant_id 3: 0..4). The host collapses the output to [D0, D1, D2, D3] (d3 fastest) so that along
// each collapsed axis each operand is either contiguous or broadcast:
//   a index = d0*sa0 + d1*sa1 + d2*sa2 + d3*A_INNER   (sa* = 0 where a is broadcast), b likewise.
// Invocation (x, y, z) computes d3 in [4x, 4x + 4) of row (d0, d1, d2) = (z / D1, z % D1, y), striding
// x over the row. VEC4 (constant_id 6): D3 % 4 == 0, so operands with X_INNER = 1 are vec4 texels.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int OP = 0;
layout(constant_id = 4) const int A_INNER = 1;  // 1: a runs along d3; 0: a is constant along d3
layout(constant_id = 5) const int B_INNER = 1;
layout(constant_id = 6) const bool VEC4 = false;

layout(binding = 0) uniform samplerBuffer a;
layout(binding = 1) uniform samplerBuffer b;
layout(std430, binding = 2) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push { uint D0, D1, D2, D3, sa0, sa1, sa2, sb0, sb1, sb2; };

vec4 load(samplerBuffer source, bool runs, uint base, uint d3) {
  if (!runs) return vec4(texelFetch(source, int(base)).x);
  if (VEC4) return texelFetch(source, int((base + d3) / 4u));
  const uint last = D3 - 1u;  // clamped reads past the row's end are discarded below
  return vec4(texelFetch(source, int(base + min(d3, last))).x, texelFetch(source, int(base + min(d3 + 1u, last))).x,
              texelFetch(source, int(base + min(d3 + 2u, last))).x, texelFetch(source, int(base + min(d3 + 3u, last))).x);
}

vec4 apply(vec4 x, vec4 z) {
  if (OP == 0) return x + z;
  if (OP == 1) return x - z;
  if (OP == 2) return x * z;
  if (OP == 3) return x / z;
  return x;
}

void main() {
  const uint d2 = gl_GlobalInvocationID.y;
  const uint d1 = gl_GlobalInvocationID.z % D1;
  const uint d0 = gl_GlobalInvocationID.z / D1;
  const uint row = (d0 * D1 + d1) * D2 + d2;
  const uint baseA = d0 * sa0 + d1 * sa1 + d2 * sa2;
  const uint baseB = d0 * sb0 + d1 * sb1 + d2 * sb2;
  const uint stride = 4u * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint d3 = 4u * gl_GlobalInvocationID.x; d3 < D3; d3 += stride) {
    const vec4 x = load(a, A_INNER == 1, baseA, d3);
    const vec4 z = OP == 4 ? vec4(0.0) : load(b, B_INNER == 1, baseB, d3);
    const vec4 result = apply(x, z);
    const uint at = row * D3 + d3;
    y[at] = result.x;
    if (d3 + 1u < D3) y[at + 1u] = result.y;
    if (d3 + 2u < D3) y[at + 2u] = result.z;
    if (d3 + 3u < D3) y[at + 3u] = result.w;
  }
}
