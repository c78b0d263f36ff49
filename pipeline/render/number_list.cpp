#include "pipeline/render/number_list.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "runtime/error.h"

namespace smokesvd::render {

std::vector<double> parseNumberList(const std::string& text, const std::string& what) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    char* end = nullptr;
    const double value = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(value))
      throw Error(what + ": '" + text + "' is not a comma-separated list of numbers");
    values.push_back(value);
  }
  if (values.empty()) throw Error(what + ": expected at least one number");
  return values;
}

}  // namespace smokesvd::render
