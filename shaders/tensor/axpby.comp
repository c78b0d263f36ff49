#version 450
#extension GL_GOOGLE_include_directive : require
// out[i] = alpha * x[i] + beta * y[i] for i < n. With beta = 0 this is scale; out may be y (axpy in place),
// since each invocation reads its items before writing them.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer x4;
layout(binding = 1) uniform samplerBuffer y4;
layout(std430, binding = 2) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push { uint n; float alpha; float beta; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  vec4 value = alpha * texelFetch(x4, int(item));
  if (beta != 0.0) value += beta * texelFetch(y4, int(item));
  result[item] = value;
}
