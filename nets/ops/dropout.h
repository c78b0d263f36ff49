// Dropout kernel (shaders/nn/dropout.comp): a mask drawn from a counter-based hash of (seed, element
// index), so it needs no state and the same (seed, shape) always gives the same mask.
#pragma once

#include <cstdint>

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// y[i] = keep(seed, i) ? x[i] / (1 - p) : 0, keep(seed, i) true with probability 1 - p; p in [0, 1]
// (p = 1 drops everything). Applied to gy with the same seed it gives the backward.
void dropout(Stream& stream, const Tensor& x, float p, uint64_t seed, const Tensor& y);

}  // namespace smokesvd::ops
