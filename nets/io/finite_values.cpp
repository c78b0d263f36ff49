#include "nets/io/finite_values.h"

#include <cmath>

#include "runtime/error.h"

namespace smokesvd::io {

std::string indexText(const Shape& shape, std::size_t flat) {
  Shape index(shape.size());
  for (std::size_t axis = shape.size(); axis-- > 0;) {
    const auto extent = static_cast<std::size_t>(std::max<int64_t>(shape[axis], 1));
    index[axis] = static_cast<int64_t>(flat % extent);
    flat /= extent;
  }
  return toString(index);
}

void requireFiniteValues(std::span<const float> values, const Shape& shape, const std::string& source,
                         const std::string& what) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) continue;
    const std::string value = std::isnan(values[i]) ? "nan" : values[i] > 0 ? "inf" : "-inf";
    throw Error(source + ": element " + indexText(shape, i) + " of " + toString(shape) + " is " + value + " (" + what +
                " must be finite)");
  }
}

}  // namespace smokesvd::io
