#version 450
#extension GL_GOOGLE_include_directive : require
// Vorticity of the MAC velocity at cell centres (mantaflow's GetCentered + CurlOp + GridNorm):
//   v(c) = centred velocity, v_a(c) = ½(u_a(c) + u_a(c + e_a)) at interior cells, 0 on the outer layer,
//   ω(c) = ∇ × v by central differences, e.g. ω_x = ½(v_z(c + e_y) − v_z(c − e_y)) − ½(v_y(c + e_z) − v_y(c − e_z)),
// at interior cells (0 on the outer layer); output planes [4, nz, ny, nx] = ω_x, ω_y, ω_z, |ω|.
// Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer velocity;
layout(std430, binding = 1) writeonly buffer Vorticity { float vorticity[]; };
layout(push_constant) uniform Push { ivec3 size; };

int cells;

bool interior(ivec3 c) { return all(greaterThan(c, ivec3(0))) && all(lessThan(c, size - 1)); }

float centred(int axis, ivec3 c) {
  if (!interior(c)) return 0.0;
  const int index = cell_index(c, size);
  const ivec3 upper = c + unit_step(axis);
  return 0.5 * (texelFetch(velocity, axis * cells + index).x +
                texelFetch(velocity, axis * cells + cell_index(upper, size)).x);
}

// ½(v_component(c + e_along) − v_component(c − e_along))
float derivative(int component, int along, ivec3 c) {
  return 0.5 * (centred(component, c + unit_step(along)) - centred(component, c - unit_step(along)));
}

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  cells = cell_count(size);
  const int item = cell_index(c, size);
  vec3 omega = vec3(0.0);
  if (interior(c)) {
    omega.x = derivative(2, 1, c) - derivative(1, 2, c);
    omega.y = derivative(0, 2, c) - derivative(2, 0, c);
    omega.z = derivative(1, 0, c) - derivative(0, 1, c);
  }
  for (int a = 0; a < 3; ++a) vorticity[a * cells + item] = omega[a];
  vorticity[3 * cells + item] = length(omega);
}
