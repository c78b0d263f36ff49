#include "nets/diffusion/schedule.h"

#include <cmath>
#include <string>

#include "runtime/error.h"

namespace smokesvd::diffusion {

NoiseSchedule::NoiseSchedule(std::vector<double> betas, double betaStart, double betaEnd)
    : betas_(std::move(betas)), betaStart_(betaStart), betaEnd_(betaEnd) {
  double product = 1.0;
  for (const double beta : betas_) {
    product *= 1.0 - beta;
    alphaBars_.push_back(product);
  }
}

NoiseSchedule NoiseSchedule::linear(int steps, double betaStart, double betaEnd) {
  if (steps < 2) throw Error("noise schedule: steps must be at least 2, got " + std::to_string(steps));
  if (!(betaStart > 0 && betaEnd < 1 && betaStart <= betaEnd))
    throw Error("noise schedule: expected 0 < beta_start <= beta_end < 1");
  std::vector<double> betas(static_cast<std::size_t>(steps));
  for (int s = 0; s < steps; ++s) betas[static_cast<std::size_t>(s)] = betaStart + (betaEnd - betaStart) * s / (steps - 1);
  return NoiseSchedule(std::move(betas), betaStart, betaEnd);
}

double NoiseSchedule::beta(int step) const {
  if (step < 0 || step >= steps())
    throw Error("noise schedule: step " + std::to_string(step) + " outside [0, " + std::to_string(steps()) + ")");
  return betas_[static_cast<std::size_t>(step)];
}

double NoiseSchedule::alphaBar(int step) const {
  if (step == -1) return 1.0;
  if (step < -1 || step >= steps())
    throw Error("noise schedule: step " + std::to_string(step) + " outside [-1, " + std::to_string(steps()) + ")");
  return alphaBars_[static_cast<std::size_t>(step)];
}

double cleanEstimate(const NoiseSchedule& schedule, int step, double noisy, double epsilon) {
  const double abar = schedule.alphaBar(step);
  return (noisy - std::sqrt(1.0 - abar) * epsilon) / std::sqrt(abar);
}

}  // namespace smokesvd::diffusion
