// Finite-difference gradients in double precision, to check backward kernels against.
//
// For a CPU reference forward f: R^n -> R^m and an upstream gradient g in R^m, the vector-Jacobian
// product the backward kernel must produce is  d/dx_i <g, f(x)>, estimated by central differences
//   (<g, f(x + eps e_i)> - <g, f(x - eps e_i)>) / (2 eps).
#pragma once

#include <functional>
#include <span>
#include <vector>

namespace smokesvd::testing {

using Function = std::function<std::vector<double>(std::span<const double>)>;

std::vector<double> numericVjp(const Function& f, std::span<const double> x, std::span<const double> upstream,
                               double eps = 1e-6);

// Widening helper for references written against float data.
std::vector<double> toDouble(std::span<const float> values);

}  // namespace smokesvd::testing
