// Differentiable pooling (autograd wrappers of nets/ops/pool.h), kernel 2, stride 2, ceil mode, on
// N,C,H,W and N,C,D,H,W; every spatial size s becomes ceil(s / 2):
//
//   Var maxPool(Tape& tape, const Var& x);   // F.max_pool{2,3}d(x, 2, 2, ceil_mode=True)
//   Var avgPool(Tape& tape, const Var& x);   // F.avg_pool{2,3}d(x, 2, 2, ceil_mode=True)
//
// A window clipped at the far edge of an odd size averages over its clipped size. Max-pool gradients go
// to the first maximum of each window in (z, y, x) scan order (ties: the earliest element).
// Registered for `smokesvd op` as max_pool and avg_pool.
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var maxPool(Tape& tape, const Var& x);
Var avgPool(Tape& tape, const Var& x);

}  // namespace smokesvd::fn
