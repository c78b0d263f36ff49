// Differentiable linear layer (autograd wrapper of nets/ops/linear.h).
//
//   Var linear(Tape& tape, const Var& x, const Var& w, const Var& b);
//     y [..., out] = x [..., in] W^T + b, W [out, in], b [out] or nullptr: torch.nn.functional.linear.
//     Gradients: x <- g W, W <- g^T x (summed over leading indices), b <- g summed over leading indices.
//
// Registered for `smokesvd op` as "linear" (inputs x, w; optional b; output y).
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var linear(Tape& tape, const Var& x, const Var& w, const Var& b);

}  // namespace smokesvd::fn
