#version 450
// Arithmetic peak probe for `smokesvd bench peak`: each invocation runs `iterations` rounds of eight
// independent vec4 multiply-add chains,
//   a_j = a_j * m + d   (j < 8),   64 FLOPs per round,
// and writes the sum of its accumulators so that nothing is optimised away. The figure it gives is the
// ceiling for loop code on the device, the reference the convolution benchmarks are compared against.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(std430, binding = 0) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push {
  int iterations;
  float seed;
};

void main() {
  const uint id = gl_GlobalInvocationID.x;
  const vec4 m = vec4(0.999999);
  const vec4 d = vec4(seed * 1e-7);
  vec4 a[8];
  for (int j = 0; j < 8; ++j) a[j] = vec4(float(id) * 1e-6 + float(j));
  for (int i = 0; i < iterations; ++i)
    for (int j = 0; j < 8; ++j) a[j] = fma(a[j], m, d);
  vec4 sum = vec4(0.0);
  for (int j = 0; j < 8; ++j) sum += a[j];
  result[id] = sum.x + sum.y + sum.z + sum.w;
}
