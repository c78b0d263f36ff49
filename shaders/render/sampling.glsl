// Trilinear sampling of a [D, H, W] volume (x fastest) read through a float samplerBuffer, at a point p in
// grid coordinates (voxel (x, y, z) centred at (x + 1/2, y + 1/2, z + 1/2)).
//   zero padding:  voxels outside the grid read 0, so the value fades to 0 over the half voxel past the box;
//   clamp to edge: the point is clamped to the outermost voxel centres first.
// trilinear_corners() gives the base voxel and fractions; the weight of corner (dx, dy, dz) is
// (dx ? f.x : 1 - f.x) (dy ? f.y : 1 - f.y) (dz ? f.z : 1 - f.z).
#ifndef SMOKESVD_RENDER_SAMPLING_GLSL
#define SMOKESVD_RENDER_SAMPLING_GLSL

void trilinear_corners(vec3 p, out ivec3 base, out vec3 f) {
  const vec3 q = p - 0.5;
  const vec3 fl = floor(q);
  base = ivec3(fl);
  f = q - fl;
}

int voxel_index(ivec3 v, ivec3 size) { return (v.z * size.y + v.y) * size.x + v.x; }

bool voxel_inside(ivec3 v, ivec3 size) { return all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, size)); }

float corner_weight(ivec3 corner, vec3 f) {
  const vec3 w = mix(1.0 - f, f, vec3(corner));
  return w.x * w.y * w.z;
}

float interpolate(vec3 f, float c000, float c100, float c010, float c110, float c001, float c101, float c011,
                  float c111) {
  const float y0 = mix(mix(c000, c100, f.x), mix(c010, c110, f.x), f.y);
  const float y1 = mix(mix(c001, c101, f.x), mix(c011, c111, f.x), f.y);
  return mix(y0, y1, f.z);
}

// Corner i of a trilinear stencil in corner order: of all 8, or (in_row) of the 4 in the stencil's lower row,
// the only ones with weight when f.y = 0 (ray_in_voxel_row below).
int stencil_corners(const bool in_row) { return in_row ? 4 : 8; }
ivec3 stencil_corner(int i, const bool in_row) { return in_row ? ivec3(i & 1, 0, i >> 1) : ivec3(i & 1, (i >> 1) & 1, i >> 2); }

// The zero-padded lookup as a sum over the stencil's corners inside the grid (where the stencil leaves it).
float corner_sum_zero(samplerBuffer volume, int offset, ivec3 size, ivec3 base, vec3 f, const bool in_row) {
  float value = 0.0;
  for (int corner = 0; corner < stencil_corners(in_row); ++corner) {
    const ivec3 corner_offset = stencil_corner(corner, in_row);
    const ivec3 v = base + corner_offset;
    if (voxel_inside(v, size))
      value += corner_weight(corner_offset, f) * texelFetch(volume, offset + voxel_index(v, size)).x;
  }
  return value;
}

// `offset`: index of the volume's first voxel in the buffer (e.g. channel * voxels).
float sample_zero_at(samplerBuffer volume, int offset, ivec3 size, vec3 p) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  if (all(greaterThanEqual(base, ivec3(0))) && all(lessThan(base, size - 1))) {
    // Fast path: the whole stencil is inside the grid.
    const int i = offset + voxel_index(base, size), sy = size.x, sz = size.x * size.y;
    return interpolate(f, texelFetch(volume, i).x, texelFetch(volume, i + 1).x, texelFetch(volume, i + sy).x,
                       texelFetch(volume, i + sy + 1).x, texelFetch(volume, i + sz).x, texelFetch(volume, i + sz + 1).x,
                       texelFetch(volume, i + sz + sy).x, texelFetch(volume, i + sz + sy + 1).x);
  }
  return corner_sum_zero(volume, offset, size, base, f, false);
}

float sample_zero(samplerBuffer volume, ivec3 size, vec3 p) { return sample_zero_at(volume, 0, size, p); }

// The index of the corner quad at base b (corner_quads.comp: the corners of the square at b's height).
int quad_index(ivec3 b, ivec3 size) { return ((b.z + 1) * (size.y + 1) + b.y + 1) * (size.x + 1) + b.x + 1; }

// sample_zero() reading the stencil's two corner quads where the stencil lies inside the grid (the same
// values in the same arithmetic: the same result, bit for bit) and the volume's corners elsewhere.
float sample_zero_quads(samplerBuffer volume, samplerBuffer quads, ivec3 size, vec3 p) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  if (all(greaterThanEqual(base, ivec3(0))) && all(lessThan(base, size - 1))) {
    const int i = quad_index(base, size);
    const vec4 low = texelFetch(quads, i), high = texelFetch(quads, i + (size.x + 1) * (size.y + 1));
    return interpolate(f, low.x, low.y, low.z, low.w, high.x, high.y, high.z, high.w);
  }
  return corner_sum_zero(volume, 0, size, base, f, false);
}

// A ray that runs at the height of a row of voxel centres (direction.y = 0, origin.y - 1/2 an integer: every
// orbit camera whose image rows are the volume's, docs/rendering.md) has f.y = 0 at every sample, so the
// upper corners' weights are 0 and the lookup reads only the four corners of its own row: the same value
// (interpolate() with f.y = 0), half the fetches. Samplers that branch on it per ray keep a separate loop
// for such rays: lavapipe runs both sides of a branch under a lane mask, but leaves a loop once no lane is in it.
bool ray_in_voxel_row(vec3 origin, vec3 direction) { return direction.y == 0.0 && fract(origin.y - 0.5) == 0.0; }

float sample_zero_in_row(samplerBuffer volume, ivec3 size, vec3 p) {
  ivec3 base;
  vec3 f;
  trilinear_corners(p, base, f);
  if (base.x >= 0 && base.z >= 0 && base.x < size.x - 1 && base.z < size.z - 1 && base.y >= 0 && base.y < size.y - 1) {
    // (the top row takes the corner sum below, as sample_zero_at's stencil check sends it there: the same roundings)
    const int i = voxel_index(base, size), sz = size.x * size.y;
    return mix(mix(texelFetch(volume, i).x, texelFetch(volume, i + 1).x, f.x),
               mix(texelFetch(volume, i + sz).x, texelFetch(volume, i + sz + 1).x, f.x), f.z);
  }
  return corner_sum_zero(volume, 0, size, base, f, true);
}

vec3 clamp_to_centres(vec3 p, ivec3 size) { return clamp(p, vec3(0.5), vec3(size) - 0.5); }

// Corner voxel of a clamped lookup: the base is kept inside the grid (the weight of a corner past the edge is 0
// after clamping, except on a grid of size 1, where both corners are the same voxel).
ivec3 clamped_voxel(ivec3 v, ivec3 size) { return clamp(v, ivec3(0), size - 1); }

float sample_clamped(samplerBuffer volume, ivec3 size, vec3 p) {
  ivec3 base;
  vec3 f;
  trilinear_corners(clamp_to_centres(p, size), base, f);
  float value = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const ivec3 offset = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
    value += corner_weight(offset, f) * texelFetch(volume, voxel_index(clamped_voxel(base + offset, size), size)).x;
  }
  return value;
}

#endif
