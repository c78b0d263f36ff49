// Volume metrics (docs/evaluation.md), on the GPU with the differential operators of pipeline/physics:
//   densityRmse          sqrt(mean over the cells of (rho - rho*)^2)
//   velocityRmse         sqrt(mean over the cells of |u(c) - u*(c)|^2), |.| the length of the cell's vector of
//                        its three lower-face (MAC) components, in cells per step
//   meanAbsDivergence    mean over the cells of |sum_d u_d(c + e_d) - u_d(c)|, the MAC divergence the pressure
//                        projection drives to zero (physics::divergence, Staggering::Mac)
//   meanGradientSquared  mean over the cells of sum_k sum_d (d_d u_k)^2 of the cell-centred velocity
//                        (physics::macToCentred, physics::gradientNormSquared)
// Densities are [D, H, W], velocities planar MAC [3, D, H, W] (device tensors).
#pragma once

#include "runtime/context.h"
#include "runtime/tensor.h"

namespace smokesvd::eval {

double densityRmse(Context& context, const Tensor& density, const Tensor& reference);
double velocityRmse(Context& context, const Tensor& velocity, const Tensor& reference);

struct VelocityScores {
  double meanAbsDivergence = 0, meanGradientSquared = 0;
};
VelocityScores velocityScores(Context& context, const Tensor& velocity);

}  // namespace smokesvd::eval
