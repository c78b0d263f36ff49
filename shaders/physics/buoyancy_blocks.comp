#version 450
#extension GL_GOOGLE_include_directive : require
// buoyancy.comp for grids whose width is a multiple of 4, four cells per invocation (force_blocks.glsl):
// on every face that takes a force, the lower a-face of c with m = c − e_a,
//   u_a(c) += dt·( g_a + fρ_a·½(ρ(c) + ρ(m)) + fT_a·½(T(c) + T(m)) ),
// other faces copied. HAS_TEMPERATURE (constant_id 3) = 0: no temperature field (binding unread).
#include "obstacle_flags.glsl"
#include "multigrid_blocks.glsl"
#include "force_blocks.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int HAS_TEMPERATURE = 1;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer density;
layout(binding = 2) uniform samplerBuffer temperature;
layout(binding = 3) uniform samplerBuffer velocity;
layout(std430, binding = 4) writeonly buffer Output { vec4 result[]; };
layout(push_constant) uniform Push {
  ivec3 blocks;
  float dt;
  vec4 uniformAcceleration;
  vec4 perDensity;
  vec4 perTemperature;
};

void main() {
  const ivec3 b = dispatch_block();
  if (!block_in_grid(b, blocks)) return;
  const int t = block_index(b, blocks);
  const int plane = plane_texels(blocks);
  const vec4 flagC = texelFetch(flags, t);
  const Lower flagM = lower_neighbours(flags, t, flagC, b, blocks, float(FLAG_OBSTACLE));
  const vec4 rhoC = texelFetch(density, t);
  const Lower rhoM = lower_neighbours(density, t, rhoC, b, blocks, 0.0);
  vec4 accelerationX = uniformAcceleration.x + perDensity.x * 0.5 * (rhoC + rhoM.x);
  vec4 accelerationY = uniformAcceleration.y + perDensity.y * 0.5 * (rhoC + rhoM.y);
  vec4 accelerationZ = uniformAcceleration.z + perDensity.z * 0.5 * (rhoC + rhoM.z);
  if (HAS_TEMPERATURE != 0) {
    const vec4 tempC = texelFetch(temperature, t);
    const Lower tempM = lower_neighbours(temperature, t, tempC, b, blocks, 0.0);
    accelerationX += perTemperature.x * 0.5 * (tempC + tempM.x);
    accelerationY += perTemperature.y * 0.5 * (tempC + tempM.y);
    accelerationZ += perTemperature.z * 0.5 * (tempC + tempM.z);
  }
  result[t] = texelFetch(velocity, t) + dt * force_acts4(flagC, flagM.x) * accelerationX;
  result[plane + t] = texelFetch(velocity, plane + t) + dt * force_acts4(flagC, flagM.y) * accelerationY;
  result[2 * plane + t] = texelFetch(velocity, 2 * plane + t) + dt * force_acts4(flagC, flagM.z) * accelerationZ;
}
