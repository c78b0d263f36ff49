#version 450
// Scales a gradient in place by the clipping factor nn/clip_factor computed: grad[i] *= result[1].
// (The optimisers read the factor directly; this is for gradients used elsewhere.)
#extension GL_GOOGLE_include_directive : require
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer clip;
layout(binding = 1) uniform samplerBuffer grad4;
layout(std430, binding = 2) writeonly buffer Grad { vec4 grad_out[]; };
layout(push_constant) uniform Push { uint n; };

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  grad_out[item] = texelFetch(grad4, int(item)) * texelFetch(clip, 1).x;
}
