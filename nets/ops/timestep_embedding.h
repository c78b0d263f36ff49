// Sinusoidal timestep embedding of diffusion models: t [N] -> y [N, dim] (see docs/nn-ops.md for the
// formula and its PyTorch equivalents). Forward only: timesteps are integers and get no gradient.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

struct TimestepEmbeddingParams {
  float maxPeriod = 10000.0f;
  float frequencyShift = 1.0f;  // f_j = exp(-ln(maxPeriod) j / (half - shift)); 1: DDPM, 0: guided-diffusion
  bool cosineFirst = false;     // false: [sin, cos] (DDPM); true: [cos, sin] (guided-diffusion)
};

// y [N, dim] from t (N elements, any shape); Error if half - shift <= 0, with half = dim / 2.
void timestepEmbedding(Stream& stream, const Tensor& t, const TimestepEmbeddingParams& params, const Tensor& y);

}  // namespace smokesvd::ops
