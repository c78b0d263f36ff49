// Inflow sources, shared by inflow_density.comp and inflow_velocity.comp. A source table holds SOURCE_TEXELS
// vec4 texels per source (pipeline/physics/sources.h writes them):
//   0: centre xyz (cells), shape (0 sphere, 1 box, 2 cylinder)
//   1: size xyz (sphere: radius; box: half extents; cylinder: radius, half height), mode (0 set, 1 add)
//   2: axis xyz (cylinder, unit), density
//   3: velocity xyz (cells per step), 1 if the source sets the velocity
//   4: temperature, noise amplitude, noise scale (cells), noise seed
//   5: noise offset xyz (cells; moves the noise over time), unused
// coverage(p) = clamp(½ − sdf(p), 0, 1): 1 deeper than half a cell inside the shape, 0 half a cell
// outside, linear across the surface; sdf is the shape's signed distance in cells.
// noise(p) in [0, 1): trilinear value noise on the lattice of spacing `noise scale`, hashed with the seed.
#ifndef SMOKESVD_INFLOW_SOURCES_GLSL
#define SMOKESVD_INFLOW_SOURCES_GLSL

const int SOURCE_TEXELS = 6;

struct Source {
  vec3 centre;
  int shape;
  vec3 size;
  int mode;
  vec3 axis;
  float density;
  vec3 velocity;
  bool setsVelocity;
  float temperature;
  float noiseAmplitude;
  float noiseScale;
  uint noiseSeed;
  vec3 noiseOffset;
};

Source read_source(samplerBuffer table, int s) {
  const int base = s * SOURCE_TEXELS;
  const vec4 t0 = texelFetch(table, base), t1 = texelFetch(table, base + 1), t2 = texelFetch(table, base + 2);
  const vec4 t3 = texelFetch(table, base + 3), t4 = texelFetch(table, base + 4), t5 = texelFetch(table, base + 5);
  return Source(t0.xyz, int(t0.w), t1.xyz, int(t1.w), t2.xyz, t2.w, t3.xyz, t3.w > 0.5, t4.x, t4.y, t4.z,
                uint(t4.w), t5.xyz);
}

float source_sdf(Source s, vec3 p) {
  const vec3 d = p - s.centre;
  if (s.shape == 0) return length(d) - s.size.x;
  if (s.shape == 1) {
    const vec3 q = abs(d) - s.size;
    return length(max(q, vec3(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
  }
  const float along = dot(d, s.axis);
  const vec2 q = vec2(length(d - along * s.axis) - s.size.x, abs(along) - s.size.y);
  return length(max(q, vec2(0.0))) + min(max(q.x, q.y), 0.0);
}

float source_coverage(Source s, vec3 p) { return clamp(0.5 - source_sdf(s, p), 0.0, 1.0); }

float lattice_value(ivec3 q, uint seed) {
  uint h = uint(q.x) * 0x8da6b343u ^ uint(q.y) * 0xd8163841u ^ uint(q.z) * 0xcb1ab31fu ^ seed * 0x9e3779b9u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return float(h >> 8) / 16777216.0;
}

float source_noise(Source s, vec3 p) {
  const vec3 x = (p + s.noiseOffset) / max(s.noiseScale, 1e-3);
  const vec3 base = floor(x);
  const vec3 w = x - base;
  const ivec3 q = ivec3(base);
  float corner[8];
  for (int n = 0; n < 8; ++n) corner[n] = lattice_value(q + ivec3(n & 1, (n >> 1) & 1, n >> 2), s.noiseSeed);
  const vec4 alongX = mix(vec4(corner[0], corner[2], corner[4], corner[6]), vec4(corner[1], corner[3], corner[5], corner[7]), w.x);
  const vec2 alongY = mix(alongX.xz, alongX.yw, w.y);
  return mix(alongY.x, alongY.y, w.z);
}

#endif
