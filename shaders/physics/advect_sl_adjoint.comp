#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of one semi-Lagrangian step out = S(field) over one plane (gather form, no atomics).
// Given the upstream gradient g = ∂L/∂out and the departure points from advect_trace:
//   gradField(y) = directScale·direct(y) + Σ_x w_x(y)·g(x)
//     over interior targets x whose stencil holds y (w_x(y) its trilinear weight); the candidates
//     are the window x_d ∈ [y_d − 1 − reachHigh_d, y_d + reachLow_d] given by the plane's reach;
//   traceGrad(d, y) = [hasPrior] prior(d, y) − dt·g(y)·∂trilinear(field, p(y))/∂p_d   (0 on the outer layer)
// traceGrad is ∂L/∂v for the trace velocity of each cell, laid out [plane, 3, cells].
#include "index.glsl"
#include "advect_sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

const int REACH_BIAS = 1 << 20;

layout(binding = 0) uniform samplerBuffer upstream;
layout(binding = 1) uniform samplerBuffer field;
layout(binding = 2) uniform samplerBuffer departure;  // vec4 texels
layout(std430, binding = 3) readonly buffer Reach { int reach[]; };
layout(binding = 4) uniform samplerBuffer direct;
layout(binding = 5) uniform samplerBuffer prior;
layout(std430, binding = 6) writeonly buffer GradField { float gradField[]; };
layout(std430, binding = 7) writeonly buffer TraceGrad { float traceGrad[]; };

void main() {
  const int item = int(flat_index());
  const int cells = cellCount();
  if (item >= cells) return;
  const ivec3 y = cellOf(item);
  const int planeOffset = plane * cells;
  const int at = planeOffset + item;

  const ivec3 reachHigh = ivec3(reach[8 * plane], reach[8 * plane + 1], reach[8 * plane + 2]) - REACH_BIAS;
  const ivec3 reachLow = ivec3(reach[8 * plane + 4], reach[8 * plane + 5], reach[8 * plane + 6]) - REACH_BIAS;
  const ivec3 first = max(y - 1 - reachHigh, ivec3(1));
  const ivec3 last = min(y + reachLow, n - 2);
  float sum = 0.0;
  for (int z = first.z; z <= last.z; ++z) {
    for (int j = first.y; j <= last.y; ++j) {
      for (int i = first.x; i <= last.x; ++i) {
        const int x = planeOffset + cellIndex(ivec3(i, j, z));
        const float weight = stencilWeight(stencilAt(texelFetch(departure, x).xyz), y);
        if (weight != 0.0) sum += weight * texelFetch(upstream, x).x;
      }
    }
  }
  if (directScale != 0.0) sum += directScale * texelFetch(direct, at).x;
  gradField[at] = sum;

  vec3 gradVelocity = vec3(0.0);
  if (isInterior(y)) {
    const float g = texelFetch(upstream, at).x;
    if (g != 0.0) {
      float corner[8];
      const Stencil s = stencilAt(texelFetch(departure, at).xyz);
      fetchCorners(field, planeOffset, s, corner);
      gradVelocity = -dt * g * trilinearGradient(corner, s);
    }
  }
  for (int d = 0; d < 3; ++d) {
    const int out_ = (3 * plane + d) * cells + item;
    traceGrad[out_] = gradVelocity[d] + (hasPrior != 0 ? texelFetch(prior, out_).x : 0.0);
  }
}
