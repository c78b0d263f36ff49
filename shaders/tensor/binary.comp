#version 450
#extension GL_GOOGLE_include_directive : require
// y[i] = a[i] OP b[i] for i < n, OP in {add, sub, mul, div} (constant_id 3: 0, 1, 2, 3).
// Inputs are read as vec4 texels (the fast read path), four items per invocation.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int OP = 0;

layout(binding = 0) uniform samplerBuffer a4;
layout(binding = 1) uniform samplerBuffer b4;
layout(std430, binding = 2) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const vec4 a = texelFetch(a4, int(item));
  const vec4 b = texelFetch(b4, int(item));
  vec4 result;
  if (OP == 0) result = a + b;
  else if (OP == 1) result = a - b;
  else if (OP == 2) result = a * b;
  else result = a / b;
  y[item] = result;
}
