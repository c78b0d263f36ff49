#version 450
#extension GL_GOOGLE_include_directive : require
// Pointwise activations, forward (y = f(x)) or backward (gx = gy * f'(x)), four items per invocation.
//   relu        f = max(x, 0)                      f' = x > 0 ? 1 : 0
//   leaky relu  f = x > 0 ? x : slope x            f' = x > 0 ? 1 : slope
//   silu        f = x s(x), s = 1 / (1 + e^-x)     f' = s (1 + x (1 - s))
//   sigmoid     f = s(x)                           f' = s (1 - s)
//   tanh        f = tanh(x)                        f' = 1 - tanh(x)^2
// KIND (constant_id 3): 0 relu, 1 leaky relu, 2 silu, 3 sigmoid, 4 tanh. BACKWARD (constant_id 4): 0 or 1.
// Bindings: x (vec4 texels), gy (vec4 texels, read only when BACKWARD), out (y or gx).
#include "index.glsl"
#include "sigmoid.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int KIND = 0;
layout(constant_id = 4) const int BACKWARD = 0;

layout(binding = 0) uniform samplerBuffer x4;
layout(binding = 1) uniform samplerBuffer gy4;
layout(std430, binding = 2) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push { uint n; float slope; };

// tanh(x) = sign(x) (1 - e) / (1 + e) with e = exp(-2|x|), and 1 - tanh^2 = 4 e / (1 + e)^2. Below
// |x| = 1/4, where 1 - e cancels, the odd Taylor series to x^9 is accurate to float epsilon.
vec4 stableTanh(vec4 x, out vec4 derivative) {
  const vec4 a = abs(x);
  const vec4 e = exp(-2.0 * a);
  const vec4 x2 = x * x;
  const vec4 series = a * (1.0 + x2 * (-1.0 / 3.0 + x2 * (2.0 / 15.0 + x2 * (-17.0 / 315.0 + x2 * (62.0 / 2835.0)))));
  derivative = 4.0 * e / ((1.0 + e) * (1.0 + e));
  return sign(x) * mix((1.0 - e) / (1.0 + e), series, lessThan(a, vec4(0.25)));
}

vec4 forward(vec4 x) {
  vec4 unused;
  if (KIND == 0) return max(x, 0.0);
  if (KIND == 1) return mix(slope * x, x, greaterThan(x, vec4(0.0)));
  if (KIND == 2) return silu(x);
  if (KIND == 3) return sigmoid(x, unused);
  return stableTanh(x, unused);
}

// gy f'(x); relu and leaky relu select rather than multiply, so gx is exactly 0, gy or slope gy.
vec4 backward(vec4 x, vec4 gy) {
  if (KIND == 0) return mix(vec4(0.0), gy, greaterThan(x, vec4(0.0)));
  if (KIND == 1) return mix(slope * gy, gy, greaterThan(x, vec4(0.0)));
  vec4 derivative;
  if (KIND == 4) {
    stableTanh(x, derivative);
    return gy * derivative;
  }
  if (KIND == 2) return siluBackward(x, gy);
  vec4 complement;
  const vec4 s = sigmoid(x, complement);
  return gy * s * complement;
}

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const vec4 x = texelFetch(x4, int(item));
  result[item] = BACKWARD != 0 ? backward(x, texelFetch(gy4, int(item))) : forward(x);
}
