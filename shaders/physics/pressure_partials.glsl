// Per-workgroup partial reductions for the pressure solver's dot products and maxima: every invocation
// of the workgroup calls workgroup_sum / workgroup_max in uniform control flow; invocation 0 gets the
// result and stores it at partial slot workgroup_slot() (the flat workgroup index of a dispatchFlat).
// Include after the local_size layout; the workgroup size must be a power of two.
#ifndef SMOKESVD_PRESSURE_PARTIALS_GLSL
#define SMOKESVD_PRESSURE_PARTIALS_GLSL

shared float partial_tree[gl_WorkGroupSize.x];

uint workgroup_slot() { return gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x; }

float workgroup_reduce(float value, bool take_max) {
  const uint local = gl_LocalInvocationIndex;
  barrier();
  partial_tree[local] = value;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) {
      const float other = partial_tree[local + half_];
      partial_tree[local] = take_max ? max(partial_tree[local], other) : partial_tree[local] + other;
    }
    barrier();
  }
  return partial_tree[0];
}

float workgroup_sum(float value) { return workgroup_reduce(value, false); }
float workgroup_max(float value) { return workgroup_reduce(value, true); }

#endif
