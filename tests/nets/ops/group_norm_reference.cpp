#include "tests/nets/ops/group_norm_reference.h"

#include <cmath>

namespace smokesvd::testing {

GroupNormLayout groupNormLayout(const Shape& shape, int64_t groups) {
  return {shape[0], shape[1], groups, numElements(shape) / (shape[0] * shape[1])};
}

std::vector<double> groupNormReference(std::span<const double> x, std::span<const double> gamma,
                                       std::span<const double> beta, const GroupNormLayout& l, double eps) {
  std::vector<double> y(x.size());
  const int64_t m = l.groupSize();
  for (int64_t b = 0; b < l.batch * l.groups; ++b) {
    const auto block = x.subspan(static_cast<std::size_t>(b * m), static_cast<std::size_t>(m));
    double mean = 0, var = 0;
    for (double v : block) mean += v;
    mean /= static_cast<double>(m);
    for (double v : block) var += (v - mean) * (v - mean);
    const double rstd = 1.0 / std::sqrt(var / static_cast<double>(m) + eps);
    for (int64_t i = 0; i < m; ++i) {
      const int64_t c = (b % l.groups) * (l.channels / l.groups) + i / l.planeSize;
      const std::size_t at = static_cast<std::size_t>(b * m + i);
      y[at] = (x[at] - mean) * rstd * gamma[static_cast<std::size_t>(c)] + beta[static_cast<std::size_t>(c)];
    }
  }
  return y;
}

std::vector<double> groupNormSiluReference(std::span<const double> x, std::span<const double> gamma,
                                           std::span<const double> beta, const GroupNormLayout& l, double eps) {
  std::vector<double> y = groupNormReference(x, gamma, beta, l, eps);
  for (double& v : y) v = v / (1.0 + std::exp(-v));
  return y;
}

}  // namespace smokesvd::testing
