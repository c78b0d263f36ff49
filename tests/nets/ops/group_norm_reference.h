// Plain-loop CPU references of GroupNorm in double, for the kernel tests (group_norm_test.cpp,
// norm_silu_conv_test.cpp).
#pragma once

#include <span>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::testing {

// x [N, C, spatial...] split into `groups` groups of channels; planeSize = the product of the spatial sizes.
struct GroupNormLayout {
  int64_t batch, channels, groups, planeSize;
  int64_t groupSize() const { return channels / groups * planeSize; }
};

GroupNormLayout groupNormLayout(const Shape& shape, int64_t groups);

// F.group_norm: mean and biased variance per (sample, group), two passes.
std::vector<double> groupNormReference(std::span<const double> x, std::span<const double> gamma,
                                       std::span<const double> beta, const GroupNormLayout& l, double eps);
// F.silu of it.
std::vector<double> groupNormSiluReference(std::span<const double> x, std::span<const double> gamma,
                                           std::span<const double> beta, const GroupNormLayout& l, double eps);

}  // namespace smokesvd::testing
