// MacCormack's correction and mantaflow's revert-to-first-order clamp (clampMode 2), shared by the
// prepare pass, the correction pass and its adjoint. Requires advect_sampling.glsl. The flag tests
// read the per-cell masks of advect_masks.comp.
//
// At an interior cell c with trace velocity v, first-order value fwd(c) = SL(field, dt)(c) and
// bwd(c) = trilinear(fwd, c + ½ + v·dt):
//   corrected(c): a scalar plane is corrected where c is fluid; MAC component m where c and c − e_m
//                 are fluid (c − e_m only when c_m > 0);
//   mc(c) = fwd(c) + strength·½·(field(c) − bwd(c)) where corrected, else fwd(c);
//   the correction is kept only if mc lies in [low, high], the range of the field over the 8 stencil
//   cells with base clamp(trunc(c − v·dt), 0, n − 2): for a scalar plane only cells flagged fluid or
//   empty count (none: revert); a MAC plane needs c and c − e_m fluid or empty and counts all 8.
// Where no correction can stand the prepare pass stores the empty range low = +inf, high = −inf.
#ifndef SMOKESVD_ADVECT_MACCORMACK_GLSL
#define SMOKESVD_ADVECT_MACCORMACK_GLSL

float infinity() { return uintBitsToFloat(0x7f800000u); }

// The masks of cell c (advect_masks.comp has the bits).
uint masksAt(samplerBuffer masks, ivec3 c) { return uint(texelFetch(masks, cellIndex(c)).x); }
bool hasBit(uint bits, int bit) { return (bits & (1u << bit)) != 0u; }

// The range [low, high] a corrected value must stay in, given the forward stencil's corners (reused
// when the clamp's base, computed as mantaflow does from c − v·dt, is the same cell).
vec2 correctionRange(samplerBuffer masks, samplerBuffer field, ivec3 c, vec3 v, Stencil forward, float corner[8]) {
  const vec2 none = vec2(infinity(), -infinity());
  const uint own = masksAt(masks, c);
  if (MODE == 0 ? !hasBit(own, 0) : !(hasBit(own, 1 + MODE) && hasBit(own, 4 + MODE))) return none;
  const ivec3 base = clamp(ivec3(vec3(c) - v * dt), ivec3(0), n - 2);
  if (base != forward.base) {
    Stencil clampStencil = forward;
    clampStencil.base = base;
    fetchCorners(field, plane * cellCount(), clampStencil, corner);
  }
  const uint block = MODE == 0 ? masksAt(masks, base) >> 8 : 0xffu;
  vec2 range = none;
  for (int k = 0; k < 8; ++k)
    if (hasBit(block, k)) range = vec2(min(range.x, corner[k]), max(range.y, corner[k]));
  return range;
}

// The corrected value at interior cell c from the prepare pass's per-cell data:
// trace = (v, field(c)), bounds = (low, high, fwd(c), ·). `kept` tells whether the correction stands.
float macCormack(samplerBuffer firstOrder, ivec3 c, vec4 trace, vec4 bounds, out bool kept) {
  kept = false;
  if (!(bounds.x <= bounds.y)) return bounds.z;
  float corner[8];
  const Stencil back = stencilAt(departurePoint(c, trace.xyz, -dt));
  fetchCorners(firstOrder, plane * cellCount(), back, corner);
  const float mc = bounds.z + strength * 0.5 * (trace.w - trilinear(corner, back));
  kept = mc >= bounds.x && mc <= bounds.y;
  return kept ? mc : bounds.z;
}

#endif
