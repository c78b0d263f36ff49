// Full reductions of a tensor to one value: sum, max, mean. Two passes: up to 256 workgroups each
// reduce a grid-strided share of the input, then one workgroup reduces their partials.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

enum class Reduction { Sum = 0, Max = 1, Mean = 2 };

// out (one element) = reduction of every element of x. x must not be empty.
void reduceAll(Stream& stream, Reduction reduction, const Tensor& x, const Tensor& out);

}  // namespace smokesvd::ops
