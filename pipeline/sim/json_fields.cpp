#include "pipeline/sim/json_fields.h"

#include <algorithm>
#include <cmath>

#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

std::string describe(const nlohmann::json& value) {
  std::string text = value.dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

}  // namespace

void JsonField::fail(const std::string& expected) const {
  const std::string where = path_.empty() ? "the document" : "field '" + path_ + "'";
  throw Error(file_ + ": " + where + ": expected " + expected + ", got " + describe(*value_));
}

JsonField JsonField::at(const std::string& key) const {
  std::optional<JsonField> field = find(key);
  if (!field) throw Error(file_ + ": missing field '" + (path_.empty() ? key : path_ + "." + key) + "'");
  return *field;
}

std::optional<JsonField> JsonField::find(const std::string& key) const {
  if (!value_->is_object()) fail("an object");
  auto it = value_->find(key);
  if (it == value_->end() || it->is_null()) return std::nullopt;
  return JsonField(*it, file_, path_.empty() ? key : path_ + "." + key);
}

std::vector<JsonField> JsonField::items() const {
  if (!value_->is_array()) fail("an array");
  std::vector<JsonField> result;
  for (std::size_t i = 0; i < value_->size(); ++i)
    result.emplace_back((*value_)[i], file_, path_ + "[" + std::to_string(i) + "]");
  return result;
}

void JsonField::allowOnly(std::initializer_list<const char*> known) const {
  if (!value_->is_object()) fail("an object");
  for (auto it = value_->begin(); it != value_->end(); ++it) {
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return it.key() == k; })) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      throw Error(file_ + ": unknown field '" + (path_.empty() ? it.key() : path_ + "." + it.key()) +
                  "'; known fields here: " + list);
    }
  }
}

double JsonField::number() const {
  if (!value_->is_number()) fail("a number");
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("a finite number");
  return v;
}

double JsonField::number(double low, double high) const {
  const double v = value_->is_number() ? value_->get<double>() : NAN;
  if (!(v >= low && v <= high)) fail("a number in [" + describe(low) + ", " + describe(high) + "]");
  return v;
}

double JsonField::positive() const {
  const double v = value_->is_number() ? value_->get<double>() : NAN;
  if (!(v > 0) || !std::isfinite(v)) fail("a positive number");
  return v;
}

double JsonField::positive(double high) const {
  const double v = value_->is_number() ? value_->get<double>() : NAN;
  if (!(v > 0 && v <= high)) fail("a number above 0 and at most " + describe(high));
  return v;
}

int64_t JsonField::integer(int64_t low, int64_t high) const {
  if (!value_->is_number_integer()) fail("an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]");
  const int64_t v = value_->is_number_unsigned() ? static_cast<int64_t>(std::min<uint64_t>(value_->get<uint64_t>(), INT64_MAX))
                                                 : value_->get<int64_t>();
  if (v < low || v > high) fail("an integer in [" + std::to_string(low) + ", " + std::to_string(high) + "]");
  return v;
}

bool JsonField::boolean() const {
  if (!value_->is_boolean()) fail("true or false");
  return value_->get<bool>();
}

std::string JsonField::string() const {
  if (!value_->is_string()) fail("a string");
  return value_->get<std::string>();
}

std::string JsonField::oneOf(std::initializer_list<const char*> choices) const {
  std::string list;
  for (const char* c : choices) list += (list.empty() ? "" : ", ") + std::string("\"") + c + "\"";
  if (!value_->is_string()) fail("one of " + list);
  const std::string v = value_->get<std::string>();
  if (std::none_of(choices.begin(), choices.end(), [&](const char* c) { return v == c; })) fail("one of " + list);
  return v;
}

Vec3 JsonField::vec3() const {
  if (!value_->is_array() || value_->size() != 3 ||
      !std::all_of(value_->begin(), value_->end(), [](const nlohmann::json& v) { return v.is_number(); }))
    fail("three numbers [x, y, z]");
  Vec3 v{};
  for (int a = 0; a < 3; ++a) {
    v[a] = (*value_)[a].get<double>();
    if (!std::isfinite(v[a])) fail("three finite numbers [x, y, z]");
  }
  return v;
}

Vec3 JsonField::vec3(double limit) const {
  const Vec3 v = vec3();
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(v[a]) <= limit)) fail("three numbers [x, y, z] from " + describe(-limit) + " to " + describe(limit));
  return v;
}

Vec3 JsonField::positiveVec3(double limit) const {
  const Vec3 v = value_->is_array() && value_->size() == 3 ? vec3() : Vec3{-1, -1, -1};
  for (int a = 0; a < 3; ++a)
    if (!(v[a] > 0 && v[a] <= limit)) fail("three numbers [x, y, z] above 0 and at most " + describe(limit));
  return v;
}

}  // namespace smokesvd::sim
