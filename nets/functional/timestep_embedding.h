// Sinusoidal timestep embedding (wrapper of nets/ops/timestep_embedding.h).
//
//   Var timestepEmbedding(Tape& tape, const Var& t, int64_t dim, ops::TimestepEmbeddingParams params = {});
//     t holds N timesteps (any shape, integer values stored as float); y [N, dim]:
//       half = dim / 2, f_j = exp(-ln(maxPeriod) * j / (half - frequencyShift)), a_j = t_n f_j (j < half),
//       y[n] = [sin(a_0..a_{half-1}), cos(a_0..a_{half-1})] (or cos first), a trailing 0 when dim is odd.
//     Defaults (maxPeriod 10000, shift 1, sin first) are DDPM's and diffusers' get_timestep_embedding(t, dim);
//     shift 0 with cosineFirst is guided-diffusion's timestep_embedding(t, dim). See docs/nn-ops.md.
//     No gradient: the output never requires one (timesteps are integers).
//
// Registered for `smokesvd op` as "timestep_embedding" (t; attributes dim, max_period=10000, shift=1,
// cos_first=0); asking it for a gradient is an error.
#pragma once

#include "nets/autograd/tape.h"
#include "nets/ops/timestep_embedding.h"

namespace smokesvd::fn {

Var timestepEmbedding(Tape& tape, const Var& t, int64_t dim, ops::TimestepEmbeddingParams params = {});

}  // namespace smokesvd::fn
