// The diffusion forward process and its inversion on the autograd tape, per sample n at step s_n
// (nets/diffusion/schedule.h), for training:
//   addNoise:       x_s  = a_n x_0 + b_n eps                    a_n = sqrt(abar_{s_n}), b_n = sqrt(1 - abar_{s_n})
//   estimateClean:  x0^  = x_s / a_n - (b_n / a_n) eps^          the paper's eq. 3 (Algorithm 1, line 12)
// The per-sample factors are [N] tensors, uploaded before each submit of a recorded step
// (StepFactors), so one recording trains at every step s.
#pragma once

#include <span>
#include <vector>

#include "nets/autograd/tape.h"
#include "nets/diffusion/schedule.h"

namespace smokesvd::diffusion {

struct StepFactors {
  std::vector<float> a, b, inverseA, bOverA;  // one per sample
};
StepFactors stepFactors(const NoiseSchedule& schedule, std::span<const int> steps);

// The four factor tensors of a batch of N samples, uploaded from StepFactors before each submit.
struct StepFactorTensors {
  StepFactorTensors(Context& context, int64_t samples);
  void upload(const StepFactors& factors) const;
  Var a, b, inverseA, bOverA;  // [N], no gradient
};

Var addNoise(Tape& tape, const Var& clean, const Var& noise, const StepFactorTensors& factors);
Var estimateClean(Tape& tape, const Var& noisy, const Var& predictedNoise, const StepFactorTensors& factors);

}  // namespace smokesvd::diffusion
