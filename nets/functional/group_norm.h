// Differentiable GroupNorm (autograd wrapper of nets/ops/group_norm.h) on N,C,spatial... tensors:
//
//   Var groupNorm(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);
//   Var groupNormSilu(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);
//
// PyTorch: F.group_norm(x, groups, gamma, beta, eps) (nn.GroupNorm(groups, C, eps, affine=True));
// groupNormSilu is F.silu of it, in one pass forward and without storing the norm's output (its backward
// recomputes it): the GroupNorm-then-SiLU of a DDPM residual block.
// groups must divide C; gamma and beta are [C]. Either may be nullptr: gamma = 1, beta = 0 (affine=False).
// Gradients flow to x, gamma and beta (to each only if it requires one).
// Registered for `smokesvd op` as group_norm and group_norm_silu (inputs x, gamma, beta; attrs groups, eps).
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var groupNorm(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);
Var groupNormSilu(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps = 1e-5f);

}  // namespace smokesvd::fn
