// Plain-loop CPU references of the convolutions in double, for the kernel tests. Shapes are PyTorch's
// (4D or 5D); an empty bias means none.
#pragma once

#include <span>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::testing {

struct ConvSpec {
  int stride = 1;
  int padding = 0;
  int outputPadding = 0;  // transposed only
};

// y = conv(x, w) + b, weight [K, C, k...], output floor((in + 2p - k)/s) + 1.
std::vector<double> convReference(std::span<const double> x, const Shape& xShape, std::span<const double> w,
                                  const Shape& wShape, std::span<const double> bias, const ConvSpec& spec);
// y = convTranspose(x, w) + b, weight [C, K, k...], written as the scatter
// y[n, k, i*s - p + t] += x[n, c, i] * w[c, k, t] (independent of the gather form the kernels use).
std::vector<double> convTransposeReference(std::span<const double> x, const Shape& xShape, std::span<const double> w,
                                           const Shape& wShape, std::span<const double> bias, const ConvSpec& spec);
// dw[k, c, t] = sum_{n, o} dy[n, k, o] * x[n, c, o*s - p + t] for the conv y = conv(x, w).
std::vector<double> convWeightGradReference(std::span<const double> x, const Shape& xShape,
                                            std::span<const double> dy, const Shape& wShape, const ConvSpec& spec);

Shape referenceConvOutputShape(const Shape& xShape, const Shape& wShape, const ConvSpec& spec);
Shape referenceConvTransposeOutputShape(const Shape& xShape, const Shape& wShape, const ConvSpec& spec);

}  // namespace smokesvd::testing
