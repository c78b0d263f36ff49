// Differentiable convolutions (autograd wrappers of nets/ops/conv.h), PyTorch layouts:
//   conv2d x [N, C, H, W], w [K, C, kH, kW];  conv3d x [N, C, D, H, W], w [K, C, kD, kH, kW];
//   convTranspose2d/3d w [C, K, k...]; bias [K] or nullptr. Stride and padding are the same along every
// axis; params.outputPadding only applies to the transposed ones.
#pragma once

#include "nets/autograd/tape.h"
#include "nets/ops/conv.h"

namespace smokesvd::fn {

// With an addend (a Var of the output's shape, or nullptr): y = addend + conv(...) + b, the sum made as y is
// written (a residual connection without a pass of its own); params.inputSlope reads x through leaky ReLU.
Var conv2d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params,
           const Var& addend = nullptr);
Var conv3d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params,
           const Var& addend = nullptr);
Var convTranspose2d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params);
Var convTranspose3d(Tape& tape, const Var& x, const Var& w, const Var& bias, const ops::ConvParams& params);

}  // namespace smokesvd::fn
