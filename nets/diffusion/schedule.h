// The DDPM noise schedule and the forward process (Ho et al. 2020), with the step convention of the
// DDPM and DDIM reference code: steps s = 0 .. T-1 index beta_s, and
//   abar_s = prod_{k <= s} (1 - beta_k),     x_s = sqrt(abar_s) x_0 + sqrt(1 - abar_s) eps.
// SvDiff uses the linear schedule beta from 1e-4 to 0.02 over T = 1000 steps.
#pragma once

#include <vector>

namespace smokesvd::diffusion {

class NoiseSchedule {
 public:
  // beta_s = betaStart + (betaEnd - betaStart) s / (T - 1), s = 0 .. T-1 (numpy.linspace).
  static NoiseSchedule linear(int steps = 1000, double betaStart = 1e-4, double betaEnd = 0.02);

  int steps() const { return static_cast<int>(betas_.size()); }
  double beta(int step) const;
  // abar_s for s in [0, T); abar_{-1} = 1 (no noise), the "next" step of DDIM's last update.
  double alphaBar(int step) const;
  double betaStart() const { return betaStart_; }
  double betaEnd() const { return betaEnd_; }

 private:
  NoiseSchedule(std::vector<double> betas, double betaStart, double betaEnd);
  std::vector<double> betas_;
  std::vector<double> alphaBars_;
  double betaStart_ = 0, betaEnd_ = 0;
};

// The clean image the noise prediction implies (the paper's eq. 3), on the host:
//   x0 = (x_s - sqrt(1 - abar_s) eps) / sqrt(abar_s)
double cleanEstimate(const NoiseSchedule& schedule, int step, double noisy, double epsilon);

}  // namespace smokesvd::diffusion
