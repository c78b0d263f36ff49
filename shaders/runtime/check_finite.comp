#version 450
#extension GL_GOOGLE_include_directive : require
// The finite check's scan (runtime/finite_check.h) of what one dispatch wrote to x[0..n), given the
// copy `before` made just before the dispatch; four floats per invocation:
//   first = min over i < n with x[i] not finite and bits(x[i]) != bits(before[i]) of 4*i + kind,
//   kind 1 = NaN, 2 = +Inf, 3 = -Inf,
// kept with atomicMin in a slot the recording resets to 0xFFFFFFFF. Elements the dispatch left alone
// (a partial write: one phase of a strided grid, one part of a concatenation) are not its doing. A float
// is not finite when its exponent bits are all ones; the test is made on the bits so that no
// floating-point folding can drop it.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer x;       // vec4 texels
layout(binding = 1) uniform samplerBuffer before;  // vec4 texels
layout(std430, binding = 2) buffer Report { uint first; };
layout(push_constant) uniform Push { uint n; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const uvec4 bits = floatBitsToUint(texelFetch(x, int(item)));
  const uvec4 old = floatBitsToUint(texelFetch(before, int(item)));
  for (uint k = 0u; k < 4u && 4u * item + k < n; ++k) {
    const uint b = bits[k];
    if ((b & 0x7F800000u) != 0x7F800000u || b == old[k]) continue;
    const uint kind = (b & 0x007FFFFFu) != 0u ? 1u : ((b >> 31) == 0u ? 2u : 3u);
    atomicMin(first, 4u * (4u * item + k) + kind);
    return;
  }
}
