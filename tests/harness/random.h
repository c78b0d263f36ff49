// Seeded random inputs and poisoned outputs for kernel tests.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::testing {

// n values uniform in [low, high) from a generator seeded with `seed` (same seed, same values).
std::vector<float> randomValues(std::size_t n, uint64_t seed, float low = -1.0f, float high = 1.0f);

// A tensor filled with randomValues(numel, seed, low, high); `values` receives the host copy if given.
Tensor randomTensor(Context& context, const Shape& shape, uint64_t seed, float low = -1.0f, float high = 1.0f,
                    std::vector<float>* values = nullptr);

// A tensor whose every element is NaN, so an element a kernel forgets to write shows up in comparisons.
Tensor poisonedTensor(Context& context, const Shape& shape);

}  // namespace smokesvd::testing
