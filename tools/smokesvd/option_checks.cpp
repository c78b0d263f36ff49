#include "tools/smokesvd/option_checks.h"

#include <charconv>
#include <cmath>
#include <sstream>

namespace smokesvd::cli {
namespace {

std::string show(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Parses the whole of `text` as T; false if any character is left over or the text is not a number.
template <typename T>
bool parseWhole(const std::string& text, T& value) {
  const char* end = text.data() + text.size();
  const auto [rest, error] = std::from_chars(text.data(), end, value);
  return error == std::errc() && rest == end;
}

}  // namespace

CLI::Validator wholeNumber(int64_t low, int64_t high) {
  const std::string expected = "a whole number from " + std::to_string(low) + " to " + std::to_string(high);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        int64_t value = 0;
        if (parseWhole(text, value) && value >= low && value <= high) return "";
        return "expected " + expected + ", got '" + text + "'";
      },
      std::to_string(low) + ".." + std::to_string(high));
}

CLI::Validator number(double low, double high) {
  const std::string expected = "a number from " + show(low) + " to " + show(high);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        if (parseWhole(text, value) && std::isfinite(value) && value >= low && value <= high) return "";
        return "expected " + expected + ", got '" + text + "'";
      },
      show(low) + ".." + show(high));
}

CLI::Validator positiveNumber(double high) {
  const std::string expected = "a number above 0 and at most " + show(high);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0;
        if (parseWhole(text, value) && std::isfinite(value) && value > 0 && value <= high) return "";
        return "expected " + expected + ", got '" + text + "'";
      },
      "(0.." + show(high) + "]");
}

}  // namespace smokesvd::cli
