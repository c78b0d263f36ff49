// Partial reductions for the pressure solver's dot products and maxima, without barriers (they are
// what costs on CPU devices): each subgroup reduces its invocations' values with subgroup arithmetic
// and one of them stores the result at its own slot,
//   partial[offset + (g·S + s)],  g = flat workgroup index of the 3D dispatch, s = subgroup in it,
// S = gl_NumSubgroups. The host sizes the buffers with the device's subgroup size (pressure.h,
// partialCount). Every invocation of the workgroup must call store_sum / store_max (subgroup operations
// need uniform control flow). Including shaders enable GL_KHR_shader_subgroup_arithmetic.
#ifndef SMOKESVD_PRESSURE_PARTIALS_GLSL
#define SMOKESVD_PRESSURE_PARTIALS_GLSL

uint partial_slot() {
  const uint group =
      gl_WorkGroupID.x + gl_NumWorkGroups.x * (gl_WorkGroupID.y + gl_NumWorkGroups.y * gl_WorkGroupID.z);
  return group * gl_NumSubgroups + gl_SubgroupID;
}

#define STORE_PARTIAL_SUM(buffer, offset, value) \
  { const float total_ = subgroupAdd(value); if (subgroupElect()) buffer[(offset) + partial_slot()] = total_; }
#define STORE_PARTIAL_MAX(buffer, offset, value) \
  { const float total_ = subgroupMax(value); if (subgroupElect()) buffer[(offset) + partial_slot()] = total_; }

#endif
