#version 450
// One DDIM step (Song et al. 2021, eq. 12), elementwise, from the noise prediction eps at step t:
//   x0   = (x - sqrt(1 - abar_t) eps) / sqrt(abar_t)        the clean estimate (paper eq. 3)
//   x0   = clamp(x0, lo, hi)                                 when clipping is on
//   next = sqrt(abar_t') x0 + sqrt(1 - abar_t' - sigma^2) eps + sigma z
// The coefficients sit in a small tensor so that one recording serves every step:
//   c = [sqrt(abar_t), sqrt(1 - abar_t), sqrt(abar_t'), sqrt(1 - abar_t' - sigma^2), sigma, clip, lo, hi]
#extension GL_GOOGLE_include_directive : require
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer x4;
layout(binding = 1) uniform samplerBuffer eps4;
layout(binding = 2) uniform samplerBuffer z4;
layout(binding = 3) uniform samplerBuffer coefficients;
layout(std430, binding = 4) writeonly buffer Next { vec4 next_out[]; };
layout(std430, binding = 5) writeonly buffer Clean { vec4 x0_out[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const vec4 eps = texelFetch(eps4, int(item));
  vec4 x0 = (texelFetch(x4, int(item)) - texelFetch(coefficients, 1).x * eps) / texelFetch(coefficients, 0).x;
  if (texelFetch(coefficients, 5).x != 0.0)
    x0 = clamp(x0, vec4(texelFetch(coefficients, 6).x), vec4(texelFetch(coefficients, 7).x));
  x0_out[item] = x0;
  next_out[item] = texelFetch(coefficients, 2).x * x0 + texelFetch(coefficients, 3).x * eps +
                   texelFetch(coefficients, 4).x * texelFetch(z4, int(item));
}
