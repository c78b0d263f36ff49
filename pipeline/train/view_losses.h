// Losses and metrics over sets of views.
//   weightedViewMse(a, b, w):  sum_v w_v mean((a_v - b_v)^2) for images [V, 1, h, w] and weights w [V]
//                               (w holds the square roots of the weights, so that it scales the difference)
//   psnr(a, b):                10 log10(1 / mean((a - b)^2)) on the host, images in [0, 1]; 100 dB for a
//                               perfect match (the cap keeps averages finite)
#pragma once

#include <span>

#include "nets/autograd/tape.h"

namespace smokesvd::train {

Var weightedViewMse(Tape& tape, const Var& a, const Var& b, const Var& sqrtWeights);

double psnr(std::span<const float> a, std::span<const float> b);

}  // namespace smokesvd::train
