// A convolution of the GroupNorm-then-SiLU of its input, as one differentiable op:
//
//   Var convOfGroupNormSilu(Tape&, const Var& x, const Var& gamma, const Var& beta, int groups, float eps,
//                           const Var& w, const Var& bias, const ops::ConvParams& params, const Var& addend = nullptr);
//
//   y = addend + conv(SiLU(F.group_norm(x, groups, gamma, beta, eps)), w) + bias
//
// the function of fn::conv2d/conv3d(fn::groupNormSilu(x, ...), w, bias, params, addend), x [N, C, (D,) H, W]
// (the rank picks 2D or 3D), gamma and beta [C]. Forward it computes the norm's statistics and lets the
// convolution's padding copy normalise and activate each value as it copies it (ops::convForwardOfNormSilu),
// so the normalised tensor is never written or kept; backward, the gradient at the activated input
// (convBackwardInput) goes through the norm's SiLU backward (ops::groupNormBackward), and the weight gradient
// normalises its padding copy the same way. A pointwise convolution that runs unpadded (a 1x1 kernel on
// positions of a multiple of 4) is refused, and params.inputSlope must be 1. Gradients flow to x, gamma, beta, w, bias and
// addend (to each only if it requires one). Registered for `smokesvd op` as group_norm_silu_conv.
#pragma once

#include "nets/autograd/tape.h"
#include "nets/ops/conv.h"

namespace smokesvd::fn {

Var convOfGroupNormSilu(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps,
                        const Var& w, const Var& bias, const ops::ConvParams& params, const Var& addend = nullptr);

}  // namespace smokesvd::fn
