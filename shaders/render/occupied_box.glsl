// The box of a volume outside which every trilinear lookup reads only zeros (pipeline/render/occupied_box.h),
// and the samples of a march that can fall inside it. The volume is cut into blocks of B^3 voxels,
// B = OCCUPIED_BLOCK; a block is occupied when one of its voxels is non-zero. A lookup at p reads the voxels
// floor(p - 1/2) and the next along each axis, so it can read a non-zero voxel only where (each axis)
//   low = B min k - 1/2 <= p < high = B (max k + 1) + 1/2       over the occupied blocks k;
// outside [low, high) it reads only zeros and adds exactly 0 to a march's sum.
#ifndef SMOKESVD_RENDER_OCCUPIED_BOX_GLSL
#define SMOKESVD_RENDER_OCCUPIED_BOX_GLSL

#include "camera.glsl"

const int OCCUPIED_BLOCK = 4;
// The box is widened by this much on every side where a march meets it, so that the roundings of a
// sample's position cannot carry a sample that is taken past it.
const float OCCUPIED_MARGIN = 1.0 / 1024.0;

// The parameters j >= 0 of a march at origin + j step that can lie in [low, high): [first, last] (empty when
// first > last, as it is for an empty box, low > high): the ray's span through the widened box (ray_box).
vec2 samples_in_box(vec3 origin, vec3 step, vec3 low, vec3 high) {
  if (any(greaterThan(low, high))) return vec2(1.0, 0.0);
  return ray_box(origin, step, low - OCCUPIED_MARGIN, high + OCCUPIED_MARGIN);
}

// The first sample j = 1/2, 3/2, ... of a light march in `range` (samples_in_box).
float first_sample_in(vec2 range) { return max(0.5, ceil(range.x - 0.5) + 0.5); }

#endif
