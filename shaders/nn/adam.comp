#version 450
// One Adam / AdamW step, torch.optim.Adam and AdamW semantics, per parameter element:
//   g = grad * clip                        (clip: the global-norm clipping factor, 1 without clipping)
//   g = g + l2_decay * p                   (Adam's weight decay; 0 for AdamW)
//   p = p * param_factor                   (AdamW's decoupled decay 1 - lr wd; 1 for Adam)
//   m = m + (1 - beta1) (g - m)            (first moment, torch's lerp)
//   v = beta2 v + (1 - beta2) g^2          (second moment)
//   p = p - step_size * m / (sqrt(v) / sqrt(1 - beta2^t) + eps)   (eps added after the bias correction)
// step_size = lr / (1 - beta1^t), sqrt(1 - beta2^t) and param_factor come from the state buffer that
// nn/optimizer_step writes each step; 1 - beta1 and 1 - beta2 come computed in double, as PyTorch
// computes them (1 - float(0.999) would be off by 1.3e-5 relative). p, m and v are read through texel
// views and written in place through storage views of the same buffers (each invocation reads its items
// before writing them).
// The tensors are either one large parameter and its state, or the small parameters gathered end to end
// (nets/optim/flat_layout.h); one dispatch updates the vec4 items from first_vec4 on while 4 item < end.
// Index: workgroup w (flat), lane l, k < ITEMS: vec4 item = first_vec4 + (w ITEMS + k) local_size_x + l,
// so the lanes of a workgroup stay on adjacent texels.
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(constant_id = 3) const uint ITEMS = 2;  // vec4s per invocation

layout(binding = 0) uniform samplerBuffer state4;
layout(binding = 1) uniform samplerBuffer clip;
layout(binding = 2) uniform samplerBuffer param4;
layout(binding = 3) uniform samplerBuffer grad4;
layout(binding = 4) uniform samplerBuffer m4;
layout(binding = 5) uniform samplerBuffer v4;
layout(std430, binding = 6) writeonly buffer Param { vec4 param_out[]; };
layout(std430, binding = 7) writeonly buffer M { vec4 m_out[]; };
layout(std430, binding = 8) writeonly buffer V { vec4 v_out[]; };
layout(push_constant) uniform Push {
  uint first_vec4;
  uint end;
  float one_minus_beta1;
  float beta2;
  float one_minus_beta2;
  float eps;
  float l2_decay;
};

void main() {
  const uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * gl_NumWorkGroups.x;
  const uint first = first_vec4 + group * ITEMS * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
  if (4u * first >= end) return;
  const vec4 step0 = texelFetch(state4, 0);
  const vec4 step1 = texelFetch(state4, 1);
  const float step_size = step0.z;
  const float bias_correction2_sqrt = step0.w;
  const float param_factor = step1.x;
  const float clip_factor = texelFetch(clip, 1).x;

  for (uint k = 0u; k < ITEMS; ++k) {
    const uint item = first + k * gl_WorkGroupSize.x;
    if (4u * item >= end) return;
    vec4 p = texelFetch(param4, int(item));
    vec4 g = texelFetch(grad4, int(item)) * clip_factor;
    if (l2_decay != 0.0) g += l2_decay * p;
    p *= param_factor;
    vec4 m = texelFetch(m4, int(item));
    m += one_minus_beta1 * (g - m);
    const vec4 v = beta2 * texelFetch(v4, int(item)) + one_minus_beta2 * (g * g);
    p -= step_size * (m / (sqrt(v) / bias_correction2_sqrt + eps));
    param_out[item] = p;
    m_out[item] = m;
    v_out[item] = v;
  }
}
