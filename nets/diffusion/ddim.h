// DDIM sampling (Song et al. 2021) for an epsilon-predicting model, recorded once and submitted once
// per sampling step: only the step's coefficients (and, for eta > 0, fresh noise) are uploaded in
// between. With abar from the schedule, step t and the next lower step t' of the sequence
// (abar_{-1} = 1 after the last):
//   x0^    = (x_t - sqrt(1 - abar_t) eps) / sqrt(abar_t)              optionally clamped to [lo, hi]
//   sigma  = eta sqrt((1 - abar_t') / (1 - abar_t)) sqrt(1 - abar_t / abar_t')
//   x_t'   = sqrt(abar_t') x0^ + sqrt(1 - abar_t' - sigma^2) eps + sigma z,   z ~ N(0, I)
// eta = 0 is deterministic (DDIM), eta = 1 the DDPM-like ancestral sampler the released SmokeSVD
// code uses. The step sequence is uniform: 0, k, 2k, ... with k = T / S (the DDIM code's "uniform"
// skip), run from the highest step down; S = 1 is the one step from the highest step T - 1 (or `start`),
// whose result is the clean estimate x0^ there (for a model trained to predict it well at T - 1, v
// prediction, the posterior mean of the data given the condition). Everything random comes from the seed,
// so a seed gives the same sample.
// A start below T - 1 (SDEdit, Meng et al. 2022) samples from a given image instead of pure noise: the
// S steps are spread over [0, start] (k = floor((start + 1) / S)) and the state begins as
//   x = sqrt(abar_top) x_start + sqrt(1 - abar_top) z,   top = (S - 1) k, the highest step visited,
// so only the detail the model adds below `top` replaces that of x_start.
#pragma once

#include <cstdint>
#include <vector>

#include "nets/autograd/tape.h"
#include "nets/diffusion/schedule.h"

namespace smokesvd::diffusion {

struct DdimOptions {
  int steps = 50;        // S, sampling steps (1 .. T, and at most start + 1)
  int start = -1;        // the highest step the steps spread over: -1 is T - 1 (from pure noise)
  double eta = 1.0;      // >= 0
  bool clipClean = false;
  float clipMin = -1.0f, clipMax = 1.0f;
  uint64_t seed = 0;
  void validate(const NoiseSchedule& schedule) const;  // Error naming the field
};

// The S steps the sampler visits, ascending: 0, k, 2k, ..., (S - 1) k with k = floor((start + 1) / S);
// start -1 is trainSteps - 1 (k = floor(T / S)). S = 1 visits the highest step alone (start, or T - 1).
std::vector<int> ddimSteps(int trainSteps, int samplingSteps, int start = -1);

// What the sampler needs of a model: record the noise prediction for the state x once; before each
// submit, set whatever depends on the step (the timestep tensor a network reads, for example).
class Denoiser {
 public:
  virtual ~Denoiser() = default;
  virtual Var predictNoise(Tape& tape, const Var& x) = 0;
  virtual void setStep(int step) = 0;
};

// The coefficient tensor of one step t -> tNext (tNext = -1 after the last):
//   [sqrt(abar_t), sqrt(1 - abar_t), sqrt(abar_t'), sqrt(1 - abar_t' - sigma^2), sigma, clip, lo, hi]
std::vector<float> ddimCoefficients(const NoiseSchedule& schedule, int step, int nextStep, const DdimOptions& options);

// Records one update (shaders/nn/ddim_step.comp): from x, the noise prediction eps, fresh noise z and
// the coefficients [8], writes the next state `next` and the clean estimate `clean` (all of x's shape).
void recordDdimStep(Stream& stream, const Tensor& x, const Tensor& eps, const Tensor& z, const Tensor& coefficients,
                    const Tensor& next, const Tensor& clean);

// Draws x_T ~ N(0, I) of `shape` from the seed (or, with `start`, noises that image of `shape` to the
// highest step) and runs the sampler; returns x_0. A start step below T - 1 needs the image.
Tensor ddimSample(Context& context, Denoiser& denoiser, const NoiseSchedule& schedule, const Shape& shape,
                  const DdimOptions& options, const Tensor* start = nullptr);

}  // namespace smokesvd::diffusion
