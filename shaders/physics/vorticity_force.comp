#version 450
#extension GL_GOOGLE_include_directive : require
// Vorticity confinement (mantaflow's vorticityConfinement) from the vorticity planes of
// vorticity_field.comp, [4, nz, ny, nx] = ω_x, ω_y, ω_z, |ω|:
//   N(c) = normalise(½(|ω|(c + e_a) − |ω|(c − e_a)))_a   (0 where the gradient vanishes),
//   F(c) = ε·N(c) × ω(c) at interior cells, 0 on the outer layer,
// applied like a cell-centred force field: on every face that takes a force (force_faces.glsl), the
// lower a-face of c with m = c − e_a,  u_a(c) += dt·½(F_a(c) + F_a(m)). Other faces are copied.
// Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "force_faces.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer vorticity;
layout(binding = 2) uniform samplerBuffer velocity;
layout(std430, binding = 3) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push { ivec3 size; float dt; float strength; };

int cells;

float magnitude(ivec3 c) { return texelFetch(vorticity, 3 * cells + cell_index(c, size)).x; }

vec3 confinement(ivec3 c) {
  if (!all(greaterThan(c, ivec3(0))) || !all(lessThan(c, size - 1))) return vec3(0.0);
  vec3 gradient;
  for (int a = 0; a < 3; ++a) gradient[a] = 0.5 * (magnitude(c + unit_step(a)) - magnitude(c - unit_step(a)));
  const float norm = length(gradient);
  if (norm <= 1e-20) return vec3(0.0);
  const int index = cell_index(c, size);
  const vec3 omega = vec3(texelFetch(vorticity, index).x, texelFetch(vorticity, cells + index).x,
                          texelFetch(vorticity, 2 * cells + index).x);
  return strength * cross(gradient / norm, omega);
}

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  cells = cell_count(size);
  const int item = cell_index(c, size);
  const uint flag = cell_flag(flags, c, size);
  const vec3 forceC = confinement(c);
  for (int a = 0; a < 3; ++a) {
    const ivec3 m = c - unit_step(a);
    float u = texelFetch(velocity, a * cells + item).x;
    if (force_acts(flag, cell_flag(flags, m, size))) u += dt * 0.5 * (forceC[a] + confinement(m)[a]);
    result[a * cells + item] = u;
  }
}
