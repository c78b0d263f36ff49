// Parsing of comma-separated number lists given on the command line or as op attributes ("0,22.5,90").
#pragma once

#include <string>
#include <vector>

namespace smokesvd::render {

// Throws Error naming `what` unless `text` is one or more finite numbers separated by commas.
std::vector<double> parseNumberList(const std::string& text, const std::string& what);

}  // namespace smokesvd::render
