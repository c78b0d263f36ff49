// Plain CPU references in double for the evaluation metrics (docs/evaluation.md), straight from their definitions.
#pragma once

#include <vector>

namespace smokesvd::testing {

// Mean of (a - b)^2.
double referenceMse(const std::vector<float>& a, const std::vector<float>& b);
double referencePsnr(double mse);  // 10 log10(1 / mse), 100 at mse <= 1e-10
// Wang et al.'s mean SSIM of two row-major width x height images: 11 x 11 Gaussian window (sigma 1.5, normalised),
// K1 0.01, K2 0.03, L 1, windowed moments sum w x^2 - mu^2, every position where the window lies inside.
double referenceSsim(const std::vector<float>& a, const std::vector<float>& b, int width, int height);

// Of a planar MAC velocity [3, z, y, x] on an x by y by z grid (lower faces; faces past the last cell are 0):
// the mean over the cells of |MAC divergence|, and the mean of sum_k sum_d (d_d u_k)^2 of the cell-centred
// velocity with numpy.gradient's differences (central inside, one-sided at the ends).
double referenceMeanAbsDivergence(const std::vector<float>& u, int x, int y, int z);
double referenceMeanGradientSquared(const std::vector<float>& u, int x, int y, int z);

}  // namespace smokesvd::testing
