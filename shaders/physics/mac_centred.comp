#version 450
#extension GL_GOOGLE_include_directive : require
// Conversion between MAC and cell-centred velocity [3, D, H, W], per cell c and component d:
//   TO_CENTRED = 1: centred_d(c) = ½·(mac_d(c) + mac_d(c + e_d))   (mac_d past the last cell = 0)
//   TO_CENTRED = 0: mac_d(c)     = ½·(centred_d(c − e_d) + centred_d(c))   (centred_d before cell 0 = 0)
// Each direction is the other's transpose, so one is the other's adjoint (gradient_stencil.glsl has
// the index names).
#include "gradient_stencil.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int TO_CENTRED = 1;

layout(binding = 0) uniform samplerBuffer source;
layout(std430, binding = 1) writeonly buffer Destination { float destination[]; };

void main() {
  const ivec3 c = ivec3(gl_GlobalInvocationID);
  if (!inGrid(c)) return;
  for (int d = 0; d < 3; ++d) {
    const ivec3 neighbour = TO_CENTRED != 0 ? c + unitStep(d) : c - unitStep(d);
    const float other = inGrid(neighbour) ? valueAt(source, d, neighbour) : 0.0;
    destination[d * cellCount() + cellIndex(c)] = 0.5 * (valueAt(source, d, c) + other);
  }
}
