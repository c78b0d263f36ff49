#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of one semi-Lagrangian step out = S(field) over one plane (gather form, no atomics).
// Given the upstream gradient g = ∂L/∂out, the departure stencils from advect_trace and the windows
// from advect_window:
//   gradField(y) = directScale·direct(y) + Σ_x w_x(y)·g(x)
//     over interior targets x whose stencil holds y (w_x(y) its trilinear weight); the candidates
//     are y's tile window x_d ∈ [y_d − 1 − max o_d, y_d + max −o_d];
//   traceGrad(d, y) = [hasPrior] prior(d, y) − dt·g(y)·∂trilinear(field, q(y))/∂q_d   (0 on the outer layer)
// traceGrad is ∂L/∂v for the trace velocity of each cell, laid out [plane, 3, cells].
#include "advect_sampling.glsl"
#include "advect_tiles.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer upstream;
layout(binding = 1) uniform samplerBuffer field;
layout(binding = 2) uniform samplerBuffer departure;  // vec4 texels
layout(std430, binding = 3) readonly buffer Window { int window[]; };
layout(binding = 4) uniform samplerBuffer direct;
layout(binding = 5) uniform samplerBuffer prior;
layout(std430, binding = 6) writeonly buffer GradField { float gradField[]; };
layout(std430, binding = 7) writeonly buffer TraceGrad { float traceGrad[]; };

// The stencil stored by advect_trace.
Stencil storedStencil(vec4 stored) {
  Stencil s;
  s.base = min(ivec3(stored.xyz), n - 2);
  s.w1 = stored.xyz - vec3(s.base);
  const int slopes = int(stored.w);
  s.slope = vec3(slopes & 1, (slopes >> 1) & 1, slopes >> 2);
  return s;
}

void main() {
  const ivec3 y = invocationCell();
  if (!inGrid(y)) return;
  const int cells = cellCount();
  const int planeOffset = plane * cells;
  const int at = planeOffset + cellIndex(y);

  const int tile = 8 * (plane * tileCount() + tileIndex(y / TILE));
  float sum = 0.0;
  if (window[tile] != 0) {
    const ivec3 high = ivec3(window[tile], window[tile + 1], window[tile + 2]) - REACH_BIAS;
    const ivec3 low = ivec3(window[tile + 4], window[tile + 5], window[tile + 6]) - REACH_BIAS;
    const ivec3 first = max(y - 1 - high, ivec3(1));
    const ivec3 last = min(y + low, n - 2);
    for (int z = first.z; z <= last.z; ++z) {
      for (int j = first.y; j <= last.y; ++j) {
        for (int i = first.x; i <= last.x; ++i) {
          const int x = planeOffset + cellIndex(ivec3(i, j, z));
          const vec4 stored = texelFetch(departure, x);
          const ivec3 base = min(ivec3(stored.xyz), n - 2);
          const ivec3 o = y - base;
          if (any(lessThan(o, ivec3(0))) || any(greaterThan(o, ivec3(1)))) continue;
          const vec3 w1 = stored.xyz - vec3(base);
          const vec3 w = mix(1.0 - w1, w1, vec3(o));
          sum += w.x * w.y * w.z * texelFetch(upstream, x).x;
        }
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
      const Stencil s = storedStencil(texelFetch(departure, at));
      fetchCorners(field, planeOffset, s, corner);
      gradVelocity = -dt * g * trilinearGradient(corner, s);
    }
  }
  for (int d = 0; d < 3; ++d) {
    const int out_ = (3 * plane + d) * cells + cellIndex(y);
    traceGrad[out_] = gradVelocity[d] + (hasPrior != 0 ? texelFetch(prior, out_).x : 0.0);
  }
}
