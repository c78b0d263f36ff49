#version 450
#extension GL_GOOGLE_include_directive : require
// Sinusoidal timestep embedding, y [N, dim] from timesteps t [N]:
//   half = dim / 2,  f_j = exp(-ln(maxPeriod) * j / (half - shift)),  a_j = t[n] * f_j  for j < half,
//   y[n, j] = sin(a_j), y[n, half + j] = cos(a_j)   (COS_FIRST = 0, constant_id 3; swapped when 1),
//   y[n, dim - 1] = 0 when dim is odd.
// One invocation per element of y.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool COS_FIRST = false;

layout(binding = 0) uniform samplerBuffer t;
layout(std430, binding = 1) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push { uint N; uint dim; float logMaxPeriod; float shift; };

void main() {
  const uint item = flat_index();
  if (item >= N * dim) return;
  const uint n = item / dim;
  const uint column = item - n * dim;
  const uint half_ = dim / 2u;
  if (column >= 2u * half_) {
    y[item] = 0.0;
    return;
  }
  const bool second = column >= half_;
  const uint j = second ? column - half_ : column;
  const float angle = texelFetch(t, int(n)).x * exp(-logMaxPeriod * float(j) / (float(half_) - shift));
  y[item] = second != COS_FIRST ? cos(angle) : sin(angle);
}
