// MacCormack's correction and mantaflow's revert-to-first-order clamp (clampMode 2), shared by the
// forward kernel and its adjoint. Requires advect_sampling.glsl. Flags hold mantaflow's bits
// (1 fluid, 2 obstacle, 4 empty) as floats.
//
// At an interior cell c with trace velocity v, first-order value fwd(c) = SL(field, dt)(c) and
// bwd(c) = trilinear(fwd, c + ½ + v·dt):
//   corrected(c): a scalar plane is corrected where c is fluid; MAC component m where c and c − e_m
//                 are fluid (c − e_m only when c_m > 0);
//   mc(c) = fwd(c) + strength·½·(field(c) − bwd(c)) where corrected, else fwd(c);
//   the correction is kept only if mc lies in [min, max] of the field over the 8 stencil cells with
//   base clamp(trunc(c − v·dt), 0, n − 2): for a scalar plane only cells flagged fluid or empty
//   count (none: revert); a MAC plane needs c and c − e_m fluid or empty and counts all 8 cells.
#ifndef SMOKESVD_ADVECT_MACCORMACK_GLSL
#define SMOKESVD_ADVECT_MACCORMACK_GLSL

bool hasFlag(samplerBuffer flags, ivec3 c, uint bits) {
  return (uint(texelFetch(flags, cellIndex(c)).x) & bits) != 0u;
}

bool isCorrected(samplerBuffer flags, ivec3 c) {
  if (!hasFlag(flags, c, 1u)) return false;
  if (mode == 0) return true;
  const int m = mode - 1;
  if (c[m] == 0) return true;
  ivec3 neighbour = c;
  neighbour[m] -= 1;
  return hasFlag(flags, neighbour, 1u);
}

// Whether the corrected value mc stays within the source's range around the traced point.
bool keepsCorrection(samplerBuffer flags, samplerBuffer field, ivec3 c, vec3 v, float mc) {
  const uint fluidOrEmpty = 5u;
  if (mode != 0) {
    ivec3 neighbour = c;
    neighbour[mode - 1] -= 1;
    if (!hasFlag(flags, c, fluidOrEmpty) || !hasFlag(flags, neighbour, fluidOrEmpty)) return false;
  }
  const ivec3 base = clamp(ivec3(vec3(c) - v * dt), ivec3(0), n - 2);
  const ivec3 stride = axisStride();
  const int planeOffset = plane * cellCount();
  float low = uintBitsToFloat(0x7f800000u);
  float high = -low;
  bool found = false;
  for (int k = 0; k < 8; ++k) {
    const ivec3 corner = base + ivec3(k & 1, (k >> 1) & 1, k >> 2);
    if (mode == 0 && !hasFlag(flags, corner, fluidOrEmpty)) continue;
    const float value = texelFetch(field, planeOffset + cellIndex(corner)).x;
    low = min(low, value);
    high = max(high, value);
    found = true;
  }
  return found && mc >= low && mc <= high;
}

// The MacCormack value at interior cell c given fwd(c); `kept` tells whether the correction stands.
float macCormack(samplerBuffer flags, samplerBuffer field, samplerBuffer firstOrder, ivec3 c, vec3 v,
                 out bool kept) {
  const int at = plane * cellCount() + cellIndex(c);
  const float forward = texelFetch(firstOrder, at).x;
  kept = false;
  if (!isCorrected(flags, c)) return forward;
  float corner[8];
  const Stencil back = stencilAt(departurePoint(c, v, -dt));
  fetchCorners(firstOrder, plane * cellCount(), back, corner);
  const float mc = forward + strength * 0.5 * (texelFetch(field, at).x - trilinear(corner, back));
  kept = keepsCorrection(flags, field, c, v, mc);
  return kept ? mc : forward;
}

#endif
