#version 450
// Exponential moving average of weights, in place (torch's lerp, as swa_utils' EMA averaging):
//   shadow[i] = shadow[i] + (1 - decay) (param[i] - shadow[i])
// over one large parameter, or the small parameters gathered end to end (nets/optim/flat_layout.h).
#extension GL_GOOGLE_include_directive : require
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer shadow4;
layout(binding = 1) uniform samplerBuffer param4;
layout(std430, binding = 2) writeonly buffer Shadow { vec4 shadow_out[]; };
layout(push_constant) uniform Push { uint n; float decay; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const vec4 shadow = texelFetch(shadow4, int(item));
  shadow_out[item] = shadow + (1.0 - decay) * (texelFetch(param4, int(item)) - shadow);
}
