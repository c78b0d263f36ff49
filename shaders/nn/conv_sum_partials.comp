#version 450
#extension GL_GOOGLE_include_directive : require
// Second stage of the two-stage reductions (weight and bias gradients):
//   out[i] = sum_{j < parts} partial[j*n + i]   for i < n.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer partial;
layout(std430, binding = 1) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push {
  int n;
  int parts;
};

void main() {
  const int i = int(flat_index());
  if (i >= n) return;
  float sum = 0.0;
  for (int j = 0; j < parts; ++j) sum += texelFetch(partial, j * n + i).x;
  result[i] = sum;
}
