#version 450
#extension GL_GOOGLE_include_directive : require
// Vector-field layout conversion for one cell per invocation, cells = D*H*W:
//   TO_PLANAR = 1: planar[c * cells + cell] = interleaved[cell * 3 + c]   ([D,H,W,3] -> [3,D,H,W])
//   TO_PLANAR = 0: interleaved[cell * 3 + c] = planar[c * cells + cell]   ([3,D,H,W] -> [D,H,W,3])
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int TO_PLANAR = 1;

layout(binding = 0) uniform samplerBuffer source;
layout(std430, binding = 1) writeonly buffer Destination { float destination[]; };
layout(push_constant) uniform Push { uint cells; };

void main() {
  const uint cell = flat_index();
  if (cell >= cells) return;
  for (uint c = 0u; c < 3u; ++c) {
    if (TO_PLANAR != 0) destination[c * cells + cell] = texelFetch(source, int(cell * 3u + c)).x;
    else destination[cell * 3u + c] = texelFetch(source, int(c * cells + cell)).x;
  }
}
