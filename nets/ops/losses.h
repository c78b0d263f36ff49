// Loss kernels: each forward writes a scalar [1] (plus what its backward needs); each backward writes
// the gradient with respect to one input from the upstream gradient g [1]. Definitions with formulas
// and PyTorch equivalents: docs/nn-ops.md.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// loss = mean (a - b)^2;  ga = g * 2 (a - b) / n  (gb = -ga)
void mseLoss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& loss);
void mseLossBackward(Stream& stream, const Tensor& g, const Tensor& a, const Tensor& b, const Tensor& ga);

// loss = mean |a - b|;  ga = g * sign(a - b) / n, 0 where a = b  (gb = -ga)
void l1Loss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& loss);
void l1LossBackward(Stream& stream, const Tensor& g, const Tensor& a, const Tensor& b, const Tensor& ga);

// Row sums along the last axis (an image's width): rows[r] = sum_w (a - b)[r, w], r over every leading
// index; loss = mean_r rows[r]^2;  ga[r, w] = g * 2 rows[r] / R  (gb = -ga). rows has numel / W elements.
void rowSumLoss(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& rows, const Tensor& loss);
void rowSumLossBackward(Stream& stream, const Tensor& g, const Tensor& rows, const Tensor& ga);

// PSNR per sample from its MSE: P_n = 10 log10(range^2 / (mse_n + eps)), mse_n over all but axis 0.
struct PsnrParams {
  float dataRange = 1.0f;
  float eps = 1e-10f;
};
// mse [N] = per-sample mean (a - b)^2 (N = a.size(0))
void sampleMse(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& mse);
// psnr [1] = mean_n P_n(mse_n)
void psnr(Stream& stream, const Tensor& mse, const PsnrParams& params, const Tensor& result);
// ga = g d psnr / d a for psnr(a, b) with mse = sampleMse(a, b)  (gb = -ga)
void psnrBackward(Stream& stream, const Tensor& g, const Tensor& mse, const Tensor& a, const Tensor& b,
                  const PsnrParams& params, const Tensor& ga);
// gap [1] = mean_n (P(mseA_n) - P(mseB_n))^2
void psnrGap(Stream& stream, const Tensor& mseA, const Tensor& mseB, const PsnrParams& params, const Tensor& gap);
// gx = g d gap / d x for x the image of mseX = sampleMse(x, reference), mseOther the other image's MSE
// (the gap is symmetric, so this serves both images); the reference gets -(ga + gb).
void psnrGapBackward(Stream& stream, const Tensor& g, const Tensor& mseX, const Tensor& mseOther, const Tensor& x,
                     const Tensor& reference, const PsnrParams& params, const Tensor& gx);

// mean [1] = mean(x); loss = mean^2;  gx = g * 2 mean / n
void meanResidualSquared(Stream& stream, const Tensor& x, const Tensor& mean, const Tensor& loss);
void meanResidualSquaredBackward(Stream& stream, const Tensor& g, const Tensor& mean, const Tensor& gx);

}  // namespace smokesvd::ops
