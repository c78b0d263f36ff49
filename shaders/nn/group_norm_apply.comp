#version 450
// GroupNorm, normalisation: y = (x - mean_b) rstd_b gamma[c] + beta[c] for x [N, C, S...], written
// (x - mean) a + beta with a = rstd gamma, never x a + (beta - mean a), which cancels for large means.
// Plane p = n C + c holds S contiguous elements; its group is b = n G + c / (C / G).
// Each invocation handles 4 consecutive elements of one plane; VEC4 (constant_id 3) = 1 when S % 4 == 0,
// then x is read as vec4 texels. Grid: invocation x = element quad, workgroup y strides over planes.
// Bindings: x (texels), gamma, beta (float texels, [C]), stats (float texels, (mean, rstd) per group),
// y (storage).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gamma;
layout(binding = 2) uniform samplerBuffer beta;
layout(binding = 3) uniform samplerBuffer stats;
layout(std430, binding = 4) writeonly buffer Output { float y[]; };
layout(push_constant) uniform Push { int planeSize; int planes; int channels; int channelsPerGroup; };

void main() {
  const int first = 4 * int(gl_GlobalInvocationID.x);
  if (first >= planeSize) return;
  for (int plane = int(gl_WorkGroupID.y); plane < planes; plane += int(gl_NumWorkGroups.y)) {
    const int n = plane / channels;
    const int c = plane - n * channels;
    const int block = plane / channelsPerGroup;
    const float mean = texelFetch(stats, 2 * block).r;
    const float a = texelFetch(stats, 2 * block + 1).r * texelFetch(gamma, c).r;
    const float b = texelFetch(beta, c).r;
    const int base = plane * planeSize + first;
    if (VEC4 != 0) {
      const vec4 value = (texelFetch(x, base / 4) - mean) * a + b;
      for (int k = 0; k < 4; ++k) y[base + k] = value[k];
    } else {
      for (int k = 0; k < 4 && first + k < planeSize; ++k) y[base + k] = (texelFetch(x, base + k).r - mean) * a + b;
    }
  }
}
