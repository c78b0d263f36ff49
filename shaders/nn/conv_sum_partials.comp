#version 450
#extension GL_GOOGLE_include_directive : require
// Second stage of the two-stage reductions (weight and bias gradients):
//   out[i] = sum_{j < parts} partial[j*n + i]   for i < n.
// When VEC4S (n a multiple of 4) an invocation sums four neighbouring i at once, reading and writing vec4s
// (the same sums in the same order); otherwise one i, reading floats.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool VEC4S = false;

layout(binding = 0) uniform samplerBuffer partial;
layout(binding = 1) uniform samplerBuffer partial4;
layout(std430, binding = 2) writeonly buffer Output { vec4 result4[]; };
layout(push_constant) uniform Push {
  int n;
  int parts;
};

void main() {
  const int item = int(flat_index());
  if (VEC4S) {
    if (4 * item >= n) return;
    vec4 sum = vec4(0.0);
    for (int j = 0; j < parts; ++j) sum += texelFetch(partial4, j * (n / 4) + item);
    result4[item] = sum;
  } else {
    if (item >= n) return;
    float sum = 0.0;
    for (int j = 0; j < parts; ++j) sum += texelFetch(partial, j * n + item).x;
    result4[item / 4][item % 4] = sum;
  }
}
