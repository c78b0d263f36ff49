// Differentiable GroupNorm (autograd wrapper of nets/ops/group_norm.h) on N,C,spatial... tensors:
//
//   Var groupNorm(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);
//
// PyTorch: F.group_norm(x, groups, gamma, beta, eps) (nn.GroupNorm(groups, C, eps, affine=True)).
// groups must divide C; gamma and beta are [C]. Either may be nullptr: gamma = 1, beta = 0 (affine=False).
// Gradients flow to x, gamma and beta (to each only if it requires one).
// Registered for `smokesvd op` as group_norm (inputs x, gamma, beta; attrs groups, eps).
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var groupNorm(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);

}  // namespace smokesvd::fn
