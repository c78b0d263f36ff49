#version 450
#extension GL_GOOGLE_include_directive : require
// Buoyancy and uniform accelerations (wind, gravity) on the MAC velocity, mantaflow's addBuoyancy
// generalised: on every face that takes a force (force_faces.glsl), the lower a-face of c with
// m = c − e_a,
//   u_a(c) += dt·( g_a + fρ_a·½(ρ(c) + ρ(m)) + fT_a·½(T(c) + T(m)) ),
// g the uniform acceleration, fρ and fT the accelerations per unit of density ρ and temperature T
// (cells per step²). Other faces are copied. HAS_TEMPERATURE (constant_id 3) = 0: no temperature field
// (the binding is not read). Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "force_faces.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int HAS_TEMPERATURE = 1;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer density;
layout(binding = 2) uniform samplerBuffer temperature;
layout(binding = 3) uniform samplerBuffer velocity;
layout(std430, binding = 4) writeonly buffer Output { float result[]; };
layout(push_constant) uniform Push {
  ivec3 size;
  float dt;
  vec4 uniformAcceleration;  // xyz
  vec4 perDensity;           // xyz
  vec4 perTemperature;       // xyz
};

void main() {
  const ivec3 c = dispatch_cell();
  if (!in_grid(c, size)) return;
  const int cells = cell_count(size);
  const int item = cell_index(c, size);
  const uint flag = cell_flag(flags, c, size);
  const float rhoC = texelFetch(density, item).x;
  const float tempC = HAS_TEMPERATURE != 0 ? texelFetch(temperature, item).x : 0.0;
  for (int a = 0; a < 3; ++a) {
    const ivec3 m = c - unit_step(a);
    float u = texelFetch(velocity, a * cells + item).x;
    if (force_acts(flag, cell_flag(flags, m, size))) {
      const int mIndex = cell_index(m, size);
      const float rho = 0.5 * (rhoC + texelFetch(density, mIndex).x);
      u += dt * (uniformAcceleration[a] + perDensity[a] * rho);
      if (HAS_TEMPERATURE != 0) u += dt * perTemperature[a] * 0.5 * (tempC + texelFetch(temperature, mIndex).x);
    }
    result[a * cells + item] = u;
  }
}
