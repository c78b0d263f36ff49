// Non-finite values in data read from files (or downloaded to be written) are errors, not black pixels or
// a simulation of NaN: the first NaN or infinity is named with its index.
#pragma once

#include <span>
#include <string>

#include "runtime/tensor.h"

namespace smokesvd::io {

// "[3, 0, 17]": the multi-index of flat element `flat` in a C-order array of `shape`.
std::string indexText(const Shape& shape, std::size_t flat);

// Throws Error("<source>: element [i, j, k] of <shape> is nan (<what> must be finite)") at the first value
// that is NaN or infinite.
void requireFiniteValues(std::span<const float> values, const Shape& shape, const std::string& source,
                         const std::string& what = "the values");

}  // namespace smokesvd::io
