#version 450
#extension GL_GOOGLE_include_directive : require
// y[i] = x[i] for i < n, reading vec4 texels: the texel-read / storage-write copy path.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer x4;
layout(std430, binding = 1) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  y[item] = texelFetch(x4, int(item));
}
