// GroupNorm over N,C,S... float32 tensors (any number of spatial axes, e.g. N,C,H,W or N,C,D,H,W), as
// PyTorch's F.group_norm(x, groups, gamma, beta, eps): the channels split into `groups` consecutive
// groups; each (sample, group) is normalised by its mean and biased variance, then scaled and shifted per
// channel. Statistics are computed per chunk in two passes (the first shifted by the chunk's first
// element) and chunks merged with Chan et al.'s update, so inputs with a large mean lose no precision.
// Kernels: shaders/nn/group_norm_*.comp.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

struct GroupNormShape {
  int64_t batch = 0, channels = 0, groups = 0, planeSize = 0;  // planeSize = product of the spatial sizes
};

// Checks that x is N,C,spatial... (rank >= 3, non-empty, N C <= 65535) and that groups divides C.
GroupNormShape groupNormShape(const Shape& x, int64_t groups);

// What is applied to the normalised output z before it is written: nothing, or SiLU (z sigmoid(z), the
// norm-then-SiLU of a DDPM residual block in one pass; its backward recomputes z instead of storing it).
enum class NormActivation { None, Silu };

// stats ([N * groups, 2]): each (sample, group)'s mean and 1 / sqrt(var + eps), the first two of the
// forward's three passes (a convolution that normalises its input as it reads it needs only these).
void groupNormStats(Stream& stream, const Tensor& x, int64_t groups, float eps, const Tensor& stats);

// z = (x - mean) / sqrt(var + eps) * gamma[c] + beta[c], gamma and beta [C], y = z or SiLU(z); stats
// ([N * groups, 2]: mean, 1 / sqrt(var + eps)) is written for the backward.
void groupNormForward(Stream& stream, const Tensor& x, const Tensor& gamma, const Tensor& beta, int64_t groups,
                      float eps, const Tensor& y, const Tensor& stats,
                      NormActivation activation = NormActivation::None);

// Gradients w.r.t. x, gamma and beta from gy, using the forward's stats; `activation` as in the forward
// (beta is read only to recompute z for SiLU's derivative).
void groupNormBackward(Stream& stream, const Tensor& x, const Tensor& gamma, const Tensor& beta, const Tensor& stats,
                       int64_t groups, const Tensor& gy, const Tensor& gx, const Tensor& ggamma, const Tensor& gbeta,
                       NormActivation activation = NormActivation::None);

}  // namespace smokesvd::ops
