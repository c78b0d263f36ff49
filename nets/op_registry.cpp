#include "nets/op_registry.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "runtime/error.h"
#include "runtime/name_registry.h"

namespace smokesvd {
namespace {

NameRegistry<OpSpec>& registry() {
  static NameRegistry<OpSpec> all("op");
  return all;
}

template <typename T>
T parse(const std::string& text, const std::string& op, const std::string& name, const char* expected) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    throw Error("op " + op + ": attribute " + name + "='" + text + "' is not " + expected);
  return value;
}

}  // namespace

const std::string& OpAttrs::raw(const std::string& name) const {
  auto found = values_.find(name);
  if (found == values_.end()) throw Error("op " + op_ + " has no attribute '" + name + "'");
  return found->second;
}

double OpAttrs::number(const std::string& name) const { return parse<double>(raw(name), op_, name, "a number"); }

int64_t OpAttrs::integer(const std::string& name) const { return parse<int64_t>(raw(name), op_, name, "an integer"); }

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
  if (values.empty() || text.back() == ',') throw Error(what + ": '" + text + "' is not a comma-separated list of numbers");
  return values;
}

std::vector<double> OpAttrs::numbers(const std::string& name) const {
  return parseNumberList(raw(name), "op " + op_ + ": attribute " + name);
}

std::vector<int64_t> OpAttrs::integers(const std::string& name) const {
  constexpr double kExact = 9007199254740992.0;  // 2^53: every integer up to here is a double
  std::vector<int64_t> values;
  for (double value : numbers(name)) {
    if (value != std::trunc(value) || std::abs(value) > kExact)
      throw Error("op " + op_ + ": attribute " + name + "='" + raw(name) + "' is not a comma-separated integer list");
    values.push_back(static_cast<int64_t>(value));
  }
  return values;
}

std::string OpAttrs::text(const std::string& name) const { return raw(name); }

bool registerOp(OpSpec spec) { return registry().add(std::move(spec)); }

const std::vector<OpSpec>& registeredOps() { return registry().all(); }

const OpSpec& findOp(const std::string& name) {
  if (const OpSpec* spec = registry().find(name)) return *spec;
  throw Error("unknown op '" + name + "' (smokesvd op --list shows them all)");
}

OpAttrs resolveAttrs(const OpSpec& spec, const std::map<std::string, std::string>& given) {
  std::map<std::string, std::string> values;
  for (const AttrSpec& attr : spec.attrs) {
    auto found = given.find(attr.name);
    if (found != given.end()) values[attr.name] = found->second;
    else if (!attr.defaultValue.empty()) values[attr.name] = attr.defaultValue;
    else throw Error("op " + spec.name + ": attribute '" + attr.name + "' is required (" + attr.help + ")");
  }
  for (const auto& [name, value] : given) {
    if (!values.count(name)) throw Error("op " + spec.name + " has no attribute '" + name + "'");
  }
  return OpAttrs(spec.name, std::move(values));
}

}  // namespace smokesvd
