// Reading JSON documents field by field with errors that say where and what: every failure names the
// file, the field's path (e.g. sources[0].radius) and what was expected, and unknown fields are errors
// (a misspelt field must not be silently ignored).
#pragma once

#include <array>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/geometry.h"

namespace smokesvd::sim {

class JsonField {
 public:
  JsonField(const nlohmann::json& value, std::string file, std::string path = "")
      : value_(&value), file_(std::move(file)), path_(std::move(path)) {}

  const nlohmann::json& json() const { return *value_; }
  const std::string& path() const { return path_; }

  // Throws Error "<file>: field '<path>': expected <expected>, got <value>".
  [[noreturn]] void fail(const std::string& expected) const;

  JsonField at(const std::string& key) const;                  // a required member
  std::optional<JsonField> find(const std::string& key) const; // an optional member (null counts as absent)
  std::vector<JsonField> items() const;                         // the elements of an array
  // Fails on the first member not in `known`.
  void allowOnly(std::initializer_list<const char*> known) const;

  double number() const;
  double number(double low, double high) const;  // in [low, high]
  double positive() const;                       // > 0
  double positive(double high) const;            // in (0, high]
  int64_t integer(int64_t low, int64_t high) const;
  bool boolean() const;
  std::string string() const;
  std::string oneOf(std::initializer_list<const char*> choices) const;
  Vec3 vec3() const;
  Vec3 vec3(double limit) const;          // every component in [-limit, limit]
  Vec3 positiveVec3(double limit) const;  // every component in (0, limit]

 private:
  const nlohmann::json* value_;
  std::string file_;
  std::string path_;
};

}  // namespace smokesvd::sim
