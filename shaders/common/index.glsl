// Shared index helpers.
//
// flat_index(): the item of this invocation in a flat dispatch (Stream::dispatchFlat), which lays
// ceil(count / local_size_x) workgroups on a 2D grid:  i = gid.x + gid.y * (groups.x * local_size_x).
//
// Tensor buffers are padded to 16 bytes, so kernels that handle four floats per invocation read and
// write whole vec4s; the last one may touch up to three padding floats past the tensor's end.
#ifndef SMOKESVD_INDEX_GLSL
#define SMOKESVD_INDEX_GLSL

// The workgroup size is specialised (Kernel, constant ids 0-2). Declared here, before the helpers below
// read gl_WorkGroupSize: glslang folds gl_WorkGroupSize used before this declaration to (1, 1, 1).
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

uint flat_index() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * (gl_NumWorkGroups.x * gl_WorkGroupSize.x);
}

// The number of invocations of a flat dispatch: a kernel that strides over its items by this visits
// every item whatever the number of workgroups (one workgroup: all of them, in a fixed order).
uint flat_invocations() {
  return gl_NumWorkGroups.x * gl_NumWorkGroups.y * gl_WorkGroupSize.x;
}

#endif
