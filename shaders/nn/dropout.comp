#version 450
#extension GL_GOOGLE_include_directive : require
// Dropout with a stateless mask: y[i] = keep(i) ? x[i] * scale : 0, scale = 1 / (1 - p).
//   keep(i) = u(i) >= p,   u(i) = (hash(i ^ hash(seedLow ^ hash(seedHigh))) >> 8) / 2^24  in [0, 1)
// hash is the PCG output permutation of one LCG step on 32-bit integers, i the flat element index.
// The same kernel applied to gy gives gx (same seed, same mask). Four items per invocation.
#include "index.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer x4;
layout(std430, binding = 1) writeonly buffer Output { vec4 y[]; };
layout(push_constant) uniform Push { uint n; uint seedLow; uint seedHigh; float p; float scale; };

uint pcgHash(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

void main() {
  const uint item = flat_index();
  if (4u * item >= n) return;
  const uint key = pcgHash(seedLow ^ pcgHash(seedHigh));
  const uvec4 index = 4u * item + uvec4(0u, 1u, 2u, 3u);
  const uvec4 bits =
      uvec4(pcgHash(index.x ^ key), pcgHash(index.y ^ key), pcgHash(index.z ^ key), pcgHash(index.w ^ key));
  const vec4 u = vec4(bits >> 8u) * (1.0 / 16777216.0);
  y[item] = mix(vec4(0.0), texelFetch(x4, int(item)) * scale, greaterThanEqual(u, vec4(p)));
}
