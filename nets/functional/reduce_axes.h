// Differentiable sum and mean over chosen axes (autograd wrappers of nets/ops/reduce_axes.h).
//
//   Var sum(Tape& tape, const Var& x, std::vector<int> axes = {}, bool keepdims = false);
//   Var mean(Tape& tape, const Var& x, std::vector<int> axes = {}, bool keepdims = false);
//     torch.sum(x, dim=axes, keepdim=keepdims) and torch.mean(...). Axes may be negative (from the end);
//     an empty list reduces every axis (torch.sum(x)), giving shape [] or, with keepdims, all ones.
//     Gradient: the upstream gradient repeated along the reduced axes (divided by their element count
//     for mean).
//
// Registered for `smokesvd op` as "sum" and "mean" (x; attributes axes = comma list or "all",
// keepdims = 0 or 1).
#pragma once

#include <vector>

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var sum(Tape& tape, const Var& x, std::vector<int> axes = {}, bool keepdims = false);
Var mean(Tape& tape, const Var& x, std::vector<int> axes = {}, bool keepdims = false);

}  // namespace smokesvd::fn
