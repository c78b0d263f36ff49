// Element-by-element comparison of a kernel's output with a CPU reference.
//
// An element passes when |actual - expected| <= atol + rtol * |expected| (NaN never passes). On failure
// the message gives the number of failing elements and the worst one with its multi-index.
#pragma once

#include <gtest/gtest.h>

#include <span>
#include <vector>

#include "runtime/tensor.h"

namespace smokesvd::testing {

struct Tolerance {
  double atol = 1e-5;
  double rtol = 1e-5;
};

::testing::AssertionResult allClose(std::span<const float> actual, std::span<const double> expected,
                                    const Shape& shape, Tolerance tolerance = {});
::testing::AssertionResult allClose(std::span<const float> actual, std::span<const float> expected,
                                    const Shape& shape, Tolerance tolerance = {});
// Downloads `actual` and compares it with `expected` laid out in the tensor's shape.
::testing::AssertionResult allClose(const Tensor& actual, std::span<const double> expected, Tolerance tolerance = {});
::testing::AssertionResult allClose(const Tensor& actual, std::span<const float> expected, Tolerance tolerance = {});

}  // namespace smokesvd::testing
