#version 450
// GroupNorm backward, pass 3 of 3: the input gradient
//   gx = rstd_b (gamma[c] gy - m1_b - xhat m2_b),   xhat = (x - mean_b) rstd_b,
// with (m1, m2) = coef[b] the group means of gamma gy and gamma gy xhat (group_norm_backward_finalize).
// Plane p = n C + c holds S contiguous elements; its group is b = p / (C / G). Each invocation handles
// 4 consecutive elements of one plane; VEC4 (constant_id 3) = 1 when S % 4 == 0 (vec4 texel reads).
// Grid: invocation x = element quad, workgroup y strides over planes.
// Bindings: x, gy (texels), gamma (float texels), stats ((mean, rstd) per group), coef ((m1, m2) per
// group), gx (storage).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int VEC4 = 0;

layout(binding = 0) uniform samplerBuffer x;
layout(binding = 1) uniform samplerBuffer gy;
layout(binding = 2) uniform samplerBuffer gamma;
layout(binding = 3) uniform samplerBuffer stats;
layout(binding = 4) uniform samplerBuffer coef;
layout(std430, binding = 5) writeonly buffer Output { float gx[]; };
layout(push_constant) uniform Push { int planeSize; int planes; int channels; int channelsPerGroup; };

void main() {
  const int first = 4 * int(gl_GlobalInvocationID.x);
  if (first >= planeSize) return;
  for (int plane = int(gl_WorkGroupID.y); plane < planes; plane += int(gl_NumWorkGroups.y)) {
    const int block = plane / channelsPerGroup;
    const float g = texelFetch(gamma, plane % channels).r;
    const float mean = texelFetch(stats, 2 * block).r;
    const float rstd = texelFetch(stats, 2 * block + 1).r;
    const float m1 = texelFetch(coef, 2 * block).r;
    const float m2 = texelFetch(coef, 2 * block + 1).r;
    const int base = plane * planeSize + first;
    if (VEC4 != 0) {
      const vec4 value = rstd * (g * texelFetch(gy, base / 4) - m1 - (texelFetch(x, base / 4) - mean) * rstd * m2);
      for (int k = 0; k < 4; ++k) gx[base + k] = value[k];
    } else {
      for (int k = 0; k < 4 && first + k < planeSize; ++k) {
        const float xhat = (texelFetch(x, base + k).r - mean) * rstd;
        gx[base + k] = rstd * (g * texelFetch(gy, base + k).r - m1 - xhat * m2);
      }
    }
  }
}
