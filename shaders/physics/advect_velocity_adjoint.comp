#version 450
#extension GL_GOOGLE_include_directive : require
// Adjoint of the trace velocities: from traceGrad [planes, 3, cells] (∂L/∂v of each plane's trace
// velocity, zero on the outer layer) to ∂L/∂u of the MAC velocity [3, cells], per face y and component c:
//   MAC = 0 (one centred plane):  gradVelocity_c(y) = ½·(t_c(y) + t_c(y − e_c))
//   MAC = 1 (three MAC planes m): gradVelocity_c(y) = t_{m=c,c}(y)
//                                   + Σ_{m≠c} Σ_{a,b∈{0,1}} ¼·t_{m,c}(y + a·e_m − b·e_c)
// (transposes of the averages in advect_sampling.glsl; terms outside the grid are 0).
#include "advect_sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 4) const int MAC = 0;

layout(binding = 0) uniform samplerBuffer traceGrad;
layout(std430, binding = 1) writeonly buffer GradVelocity { float gradVelocity[]; };

float traceGradAt(int tracePlane, int component, ivec3 c) {
  return texelFetch(traceGrad, (3 * tracePlane + component) * cellCount() + cellIndex(c)).x;
}

void main() {
  const ivec3 y = invocationCell();
  if (!inGrid(y)) return;
  const int item = cellIndex(y);
  for (int c = 0; c < 3; ++c) {
    ivec3 below = y;
    below[c] -= 1;
    float sum;
    if (MAC == 0) {
      sum = 0.5 * (traceGradAt(0, c, y) + (y[c] > 0 ? traceGradAt(0, c, below) : 0.0));
    } else {
      sum = traceGradAt(c, c, y);
      for (int m = 0; m < 3; ++m) {
        if (m == c) continue;
        for (int k = 0; k < 4; ++k) {
          ivec3 x = y;
          x[m] += k & 1;
          x[c] -= k >> 1;
          if (inGrid(x)) sum += 0.25 * traceGradAt(m, c, x);
        }
      }
    }
    gradVelocity[c * cellCount() + item] = sum;
  }
}
