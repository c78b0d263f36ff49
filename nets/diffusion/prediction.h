// What a diffusion network's output means (per sample n at step s_n, a_n = sqrt(abar), b_n = sqrt(1 - abar)):
//   Noise     (epsilon prediction, DDPM):              out = eps^
//   Velocity  (v prediction, Salimans & Ho 2022):      out = v^,  v = a_n eps - b_n x_0
// and how the noise and clean estimates follow from it, given the noisy x_s = a_n x_0 + b_n eps:
//   Noise:     eps^ = out                     x0^ = x_s / a_n - (b_n / a_n) out     (the paper's eq. 3)
//   Velocity:  eps^ = b_n x_s + a_n out       x0^ = a_n x_s - b_n out
// A model is trained on the MSE of its output to its target (eps, or v). The MSE of v is that of eps
// divided by abar and that of x_0 divided by 1 - abar: where the noise drowns the image (s near T) it is
// the clean estimate's error itself, which epsilon prediction leaves almost untrained (its x0^ multiplies
// the noise error by b / a, 160 at s = 999 of the linear schedule).
#pragma once

#include <string>

#include "nets/autograd/tape.h"
#include "nets/diffusion/forward_process.h"

namespace smokesvd::diffusion {

enum class Prediction { Noise, Velocity };

// "epsilon" or "v"; anything else is an Error naming `where`.
Prediction predictionFromName(const std::string& name, const std::string& where);
std::string predictionName(Prediction prediction);

// The training target of a clean sample and its noise.
Var predictionTarget(Tape& tape, Prediction prediction, const Var& clean, const Var& noise, const StepFactorTensors& factors);
// The noise and the clean estimate the model's output implies for the noisy sample.
Var noiseFromPrediction(Tape& tape, Prediction prediction, const Var& noisy, const Var& output,
                        const StepFactorTensors& factors);
Var cleanFromPrediction(Tape& tape, Prediction prediction, const Var& noisy, const Var& output,
                        const StepFactorTensors& factors);

}  // namespace smokesvd::diffusion
