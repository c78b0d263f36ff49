#version 450
#extension GL_GOOGLE_include_directive : require
// The corners of every trilinear stencil's lower and upper square as one vec4 texel each, so that a lookup
// reads two texels instead of eight scalars (sampling.glsl, sample_zero_quads):
//   quads[q(b)] = (v[b], v[b + (1,0,0)], v[b + (0,1,0)], v[b + (1,1,0)])
// for every b in [-1, W-1] x [-1, H-1] x [-1, D] (every square a stencil can read: a stencil at base b reads
// the squares at b and b + (0,0,1)), v = 0 outside the volume,
//   q(b) = ((b.z + 1) (H + 1) + b.y + 1) (W + 1) + b.x + 1,
// the order of interpolate()'s corners. One invocation per texel.
#include "index.glsl"
#include "sampling.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer volume;
layout(std430, binding = 1) writeonly buffer Quads { vec4 quads[]; };
layout(push_constant) uniform Push {
  int width, height, depth;
};

float value_at(ivec3 v, ivec3 size) { return voxel_inside(v, size) ? texelFetch(volume, voxel_index(v, size)).x : 0.0; }

void main() {
  const uint item = flat_index();
  const int row = width + 1, plane = (height + 1) * row;
  if (item >= uint(plane * (depth + 2))) return;
  const ivec3 size = ivec3(width, height, depth);
  const ivec3 b = ivec3(int(item) % row, (int(item) / row) % (height + 1), int(item) / plane) - 1;
  quads[item] = vec4(value_at(b, size), value_at(b + ivec3(1, 0, 0), size), value_at(b + ivec3(0, 1, 0), size),
                     value_at(b + ivec3(1, 1, 0), size));
}
