// Differentiable losses to a scalar [1] (autograd wrappers of nets/ops/losses.h). a and b have equal
// shapes; images are N,C,H,W (any rank for mse, l1 and the mean residual). Formulas: docs/nn-ops.md.
//
//   Var mseLoss(Tape& tape, const Var& a, const Var& b);
//     mean (a - b)^2                                      = F.mse_loss(a, b)
//   Var l1Loss(Tape& tape, const Var& a, const Var& b);
//     mean |a - b|, subgradient 0 where a = b             = F.l1_loss(a, b)
//   Var rowSumLoss(Tape& tape, const Var& a, const Var& b);
//     L_sp: mean over rows (n, c, h) of (sum_w a - sum_w b)^2, H() summing along the last axis (width)
//                                                         = F.mse_loss(a.sum(-1), b.sum(-1))
//   Var psnr(Tape& tape, const Var& a, const Var& b, float dataRange = 1.0f);
//     mean over samples n of 10 log10(dataRange^2 / (mse_n + 1e-10)), mse_n over all but axis 0
//   Var psnrGapLoss(Tape& tape, const Var& a, const Var& b, const Var& reference, float dataRange = 1.0f);
//     NvRef's PSNR discrepancy: mean over n of (PSNR_n(a, reference) - PSNR_n(b, reference))^2
//   Var meanResidualSquared(Tape& tape, const Var& residual);
//     mean(residual)^2 over every element                 = residual.mean() ** 2
//
// Registered for `smokesvd op` as "mse_loss", "l1_loss", "row_sum_loss", "psnr" (a, b; data_range=1),
// "psnr_gap_loss" (a, b, reference; data_range=1) and "mean_residual_squared" (x); output "loss".
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var mseLoss(Tape& tape, const Var& a, const Var& b);
Var l1Loss(Tape& tape, const Var& a, const Var& b);
Var rowSumLoss(Tape& tape, const Var& a, const Var& b);
Var psnr(Tape& tape, const Var& a, const Var& b, float dataRange = 1.0f);
Var psnrGapLoss(Tape& tape, const Var& a, const Var& b, const Var& reference, float dataRange = 1.0f);
Var meanResidualSquared(Tape& tape, const Var& residual);

}  // namespace smokesvd::fn
