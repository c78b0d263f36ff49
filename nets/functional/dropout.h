// Differentiable dropout (autograd wrapper of nets/ops/dropout.h):
//
//   Var dropout(Tape& tape, const Var& x, float p, uint64_t seed, bool training);
//
// Training (training = true and gradients enabled): y = mask * x / (1 - p), the mask a stateless hash
// of (seed, element index) that keeps each element with probability 1 - p, so the same seed and shape
// give the same mask; the backward applies the same mask to the gradient. Inference (training = false,
// or inside a NoGrad scope): y is x itself (the same Var, no copy). PyTorch: F.dropout(x, p, training),
// except that the mask comes from this hash, not from PyTorch's generator. p must be in [0, 1].
// Registered for `smokesvd op` as dropout (attrs p, seed, training).
#pragma once

#include <cstdint>

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var dropout(Tape& tape, const Var& x, float p, uint64_t seed, bool training);

}  // namespace smokesvd::fn
