#version 450
#extension GL_GOOGLE_include_directive : require
// y[i] = value for i < n, one vec4 per invocation.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(std430, binding = 0) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push { uint n; float value; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  y[item] = vec4(value);
}
