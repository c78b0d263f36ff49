// The box of a volume outside which every trilinear lookup reads only zeros (pipeline/render/occupied_box.h),
// and the samples of a march that can fall inside it. The volume is cut into blocks of B^3 voxels,
// B = OCCUPIED_BLOCK; a block is occupied when one of its voxels is non-zero. A lookup at p reads the voxels
// floor(p - 1/2) and the next along each axis, so it can read a non-zero voxel only where (each axis)
//   low = B min k - 1/2 <= p < high = B (max k + 1) + 1/2       over the occupied blocks k;
// outside [low, high) it reads only zeros and adds exactly 0 to a march's sum.
#ifndef SMOKESVD_RENDER_OCCUPIED_BOX_GLSL
#define SMOKESVD_RENDER_OCCUPIED_BOX_GLSL

const int OCCUPIED_BLOCK = 4;
// The box is widened by this much on every side where a march meets it, so that the roundings of a
// sample's position cannot carry a sample that is taken past it.
const float OCCUPIED_MARGIN = 1.0 / 1024.0;

// The sample indices j of a march at origin + j step that can lie in [low, high): [first, last] (empty when
// first > last, as it is for an empty box, low > high).
vec2 samples_in_box(vec3 origin, vec3 step, vec3 low, vec3 high) {
  if (any(greaterThan(low, high))) return vec2(1.0, 0.0);
  float first = -1.0e30, last = 1.0e30;
  for (int axis = 0; axis < 3; ++axis) {
    const float from = low[axis] - OCCUPIED_MARGIN, to = high[axis] + OCCUPIED_MARGIN;
    if (step[axis] == 0.0) {
      if (origin[axis] < from || origin[axis] > to) return vec2(1.0, 0.0);
      continue;
    }
    const float a = (from - origin[axis]) / step[axis], b = (to - origin[axis]) / step[axis];
    first = max(first, min(a, b));
    last = min(last, max(a, b));
  }
  return vec2(first, last);
}

#endif
