#version 450
#extension GL_GOOGLE_include_directive : require
// First step of the MacCormack adjoint over one plane. The forward is
//   out = fwd + strength·½·K·(field − bwd),   fwd = S_v(field), bwd = S_−v(fwd),
// with K(c) = 1 where the correction is made and kept (advect_maccormack.glsl), else 0; K is held
// fixed (its switch points are measure zero). Given g = ∂L/∂out and the prepare pass's data:
//   gradBwd(c) = −strength·½·K(c)·g(c)
// from which the host continues: ∂L/∂fwd = g + S_−vᵀ gradBwd, ∂L/∂field = S_vᵀ ∂L/∂fwd − gradBwd.
#include "advect_sampling.glsl"
#include "advect_maccormack.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer firstOrder;
layout(binding = 1) uniform samplerBuffer trace;   // vec4 texels
layout(binding = 2) uniform samplerBuffer bounds;  // vec4 texels
layout(binding = 3) uniform samplerBuffer upstream;
layout(std430, binding = 4) writeonly buffer GradBwd { float gradBwd[]; };

void main() {
  const ivec3 c = invocationCell();
  if (!inGrid(c)) return;
  const int at = plane * cellCount() + cellIndex(c);
  bool kept = false;
  if (isInterior(c)) macCormack(firstOrder, c, texelFetch(trace, at), texelFetch(bounds, at), kept);
  gradBwd[at] = kept ? -strength * 0.5 * texelFetch(upstream, at).x : 0.0;
}
