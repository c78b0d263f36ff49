// The catalogue of differentiable ops, for `smokesvd op` (run any op forward and backward on .npy
// files, to check or time a kernel against another framework). Each op registers itself next to its
// autograd wrapper, with the examples the op driver test runs (nets/op_example.h):
//
//   const bool registered = registerOp({"mul", "y = a * b", {"a", "b"}, {}, {}, {"y"},
//       [](Tape& tape, const std::vector<Var>& in, const OpAttrs&) { return std::vector<Var>{mul(tape, in[0], in[1])}; },
//       {{.name = "odd shape", .inputs = {{"a", draw::uniform({3, 5})}, {"b", draw::uniform({3, 5})}}}}});
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "nets/autograd/tape.h"
#include "nets/op_example.h"

namespace smokesvd {

struct AttrSpec {
  std::string name;
  std::string defaultValue;  // empty: the attribute is required
  std::string help;
};

// Attribute values as given on the command line (or defaults), parsed on request. Errors name the op
// and the attribute and say what was expected.
// "0,22.5,90" -> {0, 22.5, 90}: one or more finite numbers separated by commas. The one parser of number
// lists, for op attributes (OpAttrs::numbers, OpAttrs::integers) and command-line flags alike; `what` names
// the flag or attribute in the Error, e.g. "--angles: '0,x' is not a comma-separated list of numbers".
std::vector<double> parseNumberList(const std::string& text, const std::string& what);

class OpAttrs {
 public:
  OpAttrs(std::string op, std::map<std::string, std::string> values) : op_(std::move(op)), values_(std::move(values)) {}
  double number(const std::string& name) const;
  int64_t integer(const std::string& name) const;
  std::vector<double> numbers(const std::string& name) const;    // "0,22.5,90" (parseNumberList)
  std::vector<int64_t> integers(const std::string& name) const;  // "1,2,3": numbers() that are all integers
  std::string text(const std::string& name) const;

 private:
  const std::string& raw(const std::string& name) const;
  std::string op_;
  std::map<std::string, std::string> values_;
};

// Whether an op has a backward; one without refuses an upstream gradient (an Error, not silent zeros).
enum class Differentiable { Yes, No };

struct OpSpec {
  std::string name;
  std::string summary;
  std::vector<std::string> inputs;          // required, in order
  std::vector<std::string> optionalInputs;  // after the required ones; nullptr when absent
  std::vector<AttrSpec> attrs;
  std::vector<std::string> outputs;
  std::function<std::vector<Var>(Tape&, const std::vector<Var>& inputs, const OpAttrs&)> apply;
  std::vector<OpExample> examples;  // at least one (tests/nets/op_driver_test.cpp)
  Differentiable differentiable = Differentiable::Yes;
};

// Throws Error if an op of that name is already registered (runtime/name_registry.h).
bool registerOp(OpSpec spec);
const std::vector<OpSpec>& registeredOps();  // sorted by name
// Throws Error listing the known ops if `name` is not one.
const OpSpec& findOp(const std::string& name);
// The attributes of `spec` filled from `given` and defaults; unknown or missing ones are errors.
OpAttrs resolveAttrs(const OpSpec& spec, const std::map<std::string, std::string>& given);

}  // namespace smokesvd
