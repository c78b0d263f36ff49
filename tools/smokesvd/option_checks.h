// Checks of command-line values whose failures say what was expected, for example
//   --width: expected a whole number from 1 to 8192, got '0'
// (CLI11's own checks print their unbounded ranges as 309-digit numbers and let nan through). Every number
// a user gives is bounded here, before anything is allocated from it.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <limits>

namespace smokesvd::cli {

// The largest side of an image any command writes, in pixels.
constexpr int kMaxImageSide = 8192;

// A whole number in [low, high], written without a fraction or exponent.
CLI::Validator wholeNumber(int64_t low, int64_t high);
// A finite number in [low, high].
CLI::Validator number(double low, double high);
// A finite number in (0, high].
CLI::Validator positiveNumber(double high = std::numeric_limits<float>::max());

}  // namespace smokesvd::cli
