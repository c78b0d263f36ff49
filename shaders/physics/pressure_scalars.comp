#version 450
#extension GL_GOOGLE_include_directive : require
// The conjugate-gradient scalars from per-subgroup partials, in one workgroup (slots in
// pressure_scalars.glsl; n partials per set):
//   STEP 0 (start):     max_b = max partial[0..n),  max_r = max partial[n..2n),
//                       mean_r = Σ partial[2n..3n) · inverseFluidCells,  rz = α = β = 0
//   STEP 1 (direction): rz_new = Σ partial,  β = rz_new / rz (0 while rz = 0),  rz = rz_new
//   STEP 2 (step):      pAp = Σ partial,  α = rz / pAp (0 if pAp = 0)
//   STEP 3 (residual):  max_r = max partial
// Each invocation reduces a strided share, then a tree in shared memory.
#include "pressure_scalars.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const int STEP = 0;

layout(binding = 0) uniform samplerBuffer partial;
layout(std430, binding = 1) buffer Scalars { float scalar[]; };
layout(push_constant) uniform Push { uint n; float inverseFluidCells; };

shared float tree[gl_WorkGroupSize.x];

float reduceSet(uint offset, bool take_max) {
  const uint local = gl_LocalInvocationIndex;
  float value = 0.0;
  for (uint i = local; i < n; i += gl_WorkGroupSize.x) {
    const float v = texelFetch(partial, int(offset + i)).x;
    value = take_max ? max(value, v) : value + v;
  }
  barrier();
  tree[local] = value;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) tree[local] = take_max ? max(tree[local], tree[local + half_]) : tree[local] + tree[local + half_];
    barrier();
  }
  return tree[0];
}

void main() {
  if (STEP == 0) {
    const float maxB = reduceSet(0u, true);
    const float maxR = reduceSet(n, true);
    const float sumR = reduceSet(2u * n, false);
    if (gl_LocalInvocationIndex == 0u) {
      scalar[SCALAR_MAX_B] = maxB;
      scalar[SCALAR_MAX_R] = maxR;
      scalar[SCALAR_MEAN_R] = sumR * inverseFluidCells;
      scalar[SCALAR_RZ] = 0.0;
      scalar[SCALAR_ALPHA] = 0.0;
      scalar[SCALAR_BETA] = 0.0;
      scalar[SCALAR_PAP] = 0.0;
    }
  } else if (STEP == 1) {
    const float rz = reduceSet(0u, false);
    if (gl_LocalInvocationIndex == 0u) {
      const float rzOld = scalar[SCALAR_RZ];
      scalar[SCALAR_BETA] = rzOld != 0.0 ? rz / rzOld : 0.0;
      scalar[SCALAR_RZ] = rz;
    }
  } else if (STEP == 2) {
    const float pAp = reduceSet(0u, false);
    if (gl_LocalInvocationIndex == 0u) {
      scalar[SCALAR_PAP] = pAp;
      scalar[SCALAR_ALPHA] = pAp != 0.0 ? scalar[SCALAR_RZ] / pAp : 0.0;
    }
  } else {
    const float maxR = reduceSet(0u, true);
    if (gl_LocalInvocationIndex == 0u) scalar[SCALAR_MAX_R] = maxR;
  }
}
