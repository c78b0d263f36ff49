#version 450
// Second pass of global-norm gradient clipping (torch.nn.utils.clip_grad_norm_ with the 2-norm):
//   norm   = sqrt(sum of the partial sums of squares written by nn/grad_norm)
//   factor = min(1, max_norm / (norm + 1e-6))
// result[0] = norm, result[1] = factor; the gradients are scaled by factor where they are used.
// One workgroup runs.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer partial;
layout(std430, binding = 1) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Push { uint count; float max_norm; };

shared float tree[gl_WorkGroupSize.x];

void main() {
  const uint local = gl_LocalInvocationID.x;
  float sum = 0.0;
  for (uint i = local; i < count; i += gl_WorkGroupSize.x) sum += texelFetch(partial, int(i)).x;
  tree[local] = sum;
  barrier();
  for (uint half_ = gl_WorkGroupSize.x / 2u; half_ > 0u; half_ /= 2u) {
    if (local < half_) tree[local] += tree[local + half_];
    barrier();
  }
  if (local == 0u) {
    const float norm = sqrt(tree[0]);
    result[0] = norm;
    result[1] = min(1.0, max_norm / (norm + 1e-6));
  }
}
