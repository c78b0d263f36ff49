#version 450
// Copies a run of channels between two N,C,... tensors (concatenation and slicing along axis 1):
//   dst[n*dstRow + dstOffset + j] = src[n*srcRow + srcOffset + j] for n < N (= y), j < length,
// where a row is one sample (C*S floats, S the spatial size) and offsets and length are channel
// counts times S. Invocation (x, n) copies j in [4x, 4x + 4), striding x over the run.
// VEC4 (constant_id 3): rows, offsets and length are multiples of 4, so the copy moves vec4 texels.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const bool VEC4 = false;

layout(binding = 0) uniform samplerBuffer src;
layout(std430, binding = 1) writeonly buffer Destination { float dst[]; };
layout(push_constant) uniform Push { uint srcRow, srcOffset, dstRow, dstOffset, length; };

void main() {
  const uint n = gl_GlobalInvocationID.y;
  const uint from = n * srcRow + srcOffset;
  const uint to = n * dstRow + dstOffset;
  const uint stride = 4u * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint j = 4u * gl_GlobalInvocationID.x; j < length; j += stride) {
    if (VEC4) {
      const vec4 value = texelFetch(src, int((from + j) / 4u));
      dst[to + j] = value.x;
      dst[to + j + 1u] = value.y;
      dst[to + j + 2u] = value.z;
      dst[to + j + 3u] = value.w;
    } else {
      for (uint l = j; l < min(j + 4u, length); ++l) dst[to + l] = texelFetch(src, int(from + l)).x;
    }
  }
}
