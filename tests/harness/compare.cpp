#include "tests/harness/compare.h"

#include <cmath>
#include <sstream>

namespace smokesvd::testing {
namespace {

std::string multiIndex(std::size_t flat, const Shape& shape) {
  std::vector<int64_t> index(shape.size());
  for (std::size_t axis = shape.size(); axis-- > 0;) {
    const int64_t extent = std::max<int64_t>(shape[axis], 1);
    index[axis] = static_cast<int64_t>(flat) % extent;
    flat /= static_cast<std::size_t>(extent);
  }
  return toString(index);
}

}  // namespace

::testing::AssertionResult allClose(std::span<const float> actual, std::span<const double> expected,
                                    const Shape& shape, Tolerance tolerance) {
  if (actual.size() != expected.size())
    return ::testing::AssertionFailure() << "sizes differ: actual " << actual.size() << ", expected " << expected.size();
  std::size_t failures = 0;
  std::size_t worst = 0;
  double worstExcess = -1;
  for (std::size_t i = 0; i < actual.size(); ++i) {
    const double difference = std::abs(static_cast<double>(actual[i]) - expected[i]);
    const double allowed = tolerance.atol + tolerance.rtol * std::abs(expected[i]);
    const bool bad = !(difference <= allowed);  // NaN fails
    if (bad) {
      ++failures;
      const double excess = std::isnan(difference) ? INFINITY : difference - allowed;
      if (excess > worstExcess) {
        worstExcess = excess;
        worst = i;
      }
    }
  }
  if (failures == 0) return ::testing::AssertionSuccess();
  std::ostringstream message;
  message.precision(9);
  message << failures << " of " << actual.size() << " elements differ (atol " << tolerance.atol << ", rtol "
          << tolerance.rtol << "); worst at " << multiIndex(worst, shape) << " in " << toString(shape)
          << ": actual " << actual[worst] << ", expected " << expected[worst];
  return ::testing::AssertionFailure() << message.str();
}

::testing::AssertionResult allClose(std::span<const float> actual, std::span<const float> expected,
                                    const Shape& shape, Tolerance tolerance) {
  std::vector<double> widened(expected.begin(), expected.end());
  return allClose(actual, widened, shape, tolerance);
}

::testing::AssertionResult allClose(const Tensor& actual, std::span<const double> expected, Tolerance tolerance) {
  return allClose(actual.download(), expected, actual.shape(), tolerance);
}

::testing::AssertionResult allClose(const Tensor& actual, std::span<const float> expected, Tolerance tolerance) {
  return allClose(actual.download(), expected, actual.shape(), tolerance);
}

}  // namespace smokesvd::testing
