// Shared index helpers.
//
// flat_index(): the item of this invocation in a flat dispatch (Stream::dispatchFlat), which lays
// ceil(count / local_size_x) workgroups on a 2D grid:  i = gid.x + gid.y * (groups.x * local_size_x).
//
// Tensor buffers are padded to 16 bytes, so kernels that handle four floats per invocation read and
// write whole vec4s; the last one may touch up to three padding floats past the tensor's end.
#ifndef SMOKESVD_INDEX_GLSL
#define SMOKESVD_INDEX_GLSL

uint flat_index() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x);
}

#endif
