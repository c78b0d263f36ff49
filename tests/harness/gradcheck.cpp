#include "tests/harness/gradcheck.h"

#include <stdexcept>

namespace smokesvd::testing {

std::vector<double> numericVjp(const Function& f, std::span<const double> x, std::span<const double> upstream,
                               double eps) {
  std::vector<double> point(x.begin(), x.end());
  std::vector<double> gradient(x.size());
  auto project = [&](const std::vector<double>& y) {
    if (y.size() != upstream.size()) throw std::invalid_argument("numericVjp: upstream size differs from f's output");
    double total = 0;
    for (std::size_t j = 0; j < y.size(); ++j) total += upstream[j] * y[j];
    return total;
  };
  for (std::size_t i = 0; i < point.size(); ++i) {
    const double original = point[i];
    point[i] = original + eps;
    const double plus = project(f(point));
    point[i] = original - eps;
    const double minus = project(f(point));
    point[i] = original;
    gradient[i] = (plus - minus) / (2 * eps);
  }
  return gradient;
}

std::vector<double> toDouble(std::span<const float> values) { return {values.begin(), values.end()}; }

}  // namespace smokesvd::testing
