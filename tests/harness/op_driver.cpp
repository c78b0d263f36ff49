#include "tests/harness/op_driver.h"

#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

#include "nets/autograd/tape.h"
#include "runtime/error.h"
#include "runtime/stream.h"
#include "runtime/tensor_guards.h"
#include "tests/harness/op_runner.h"

namespace smokesvd::testing {
namespace {

// Float32 rounding of one value, relative (2^-24), and the safety factor the rounding floor of a
// difference quotient carries: several roundings per output, and several standard deviations.
constexpr double kUnitRoundoff = 5.9604644775390625e-8;
constexpr double kRoundingFactor = 8;

std::vector<std::string> inputNames(const OpSpec& spec) {
  std::vector<std::string> names = spec.inputs;
  names.insert(names.end(), spec.optionalInputs.begin(), spec.optionalInputs.end());
  return names;
}

std::vector<std::string> attrList(const OpExample& example) {
  std::vector<std::string> list;
  for (const auto& [name, value] : example.attrs) list.push_back(name + "=" + value);
  return list;
}

HostTensor download(const Tensor& tensor) { return {tensor.shape(), tensor.download()}; }

double projected(const NamedTensors& outputs, const NamedTensors& seeds) {
  double total = 0;
  for (const auto& [name, seed] : seeds) {
    const std::vector<float>& values = outputs.at(name).values;
    for (std::size_t i = 0; i < values.size(); ++i) total += static_cast<double>(seed.values[i]) * values[i];
  }
  return total;
}

// Float32 rounding in <g, f(x + h d)> - <g, f(x - h d)>: each output that differs carries independent
// rounding errors of its own size, so they add up as a root sum of squares.
double roundingOfDifference(const NamedTensors& plus, const NamedTensors& minus, const NamedTensors& seeds) {
  double squares = 0;
  for (const auto& [name, seed] : seeds) {
    const std::vector<float>& p = plus.at(name).values;
    const std::vector<float>& m = minus.at(name).values;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p[i] == m[i]) continue;
      const double size = std::abs(seed.values[i]) * (std::abs(p[i]) + std::abs(m[i]));
      squares += size * size;
    }
  }
  return kRoundingFactor * kUnitRoundoff * std::sqrt(squares);
}

// Probe directions for an input of n elements: two dense random ones, then single elements (first,
// last, one in between), which catch a wrong gradient at the edges a dense probe averages away.
std::vector<std::pair<std::string, std::vector<double>>> probes(std::size_t n, uint64_t seed) {
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> value(-1, 1);
  std::vector<std::pair<std::string, std::vector<double>>> result;
  for (int dense = 0; dense < 2; ++dense) {
    std::vector<double> d(n);
    for (double& v : d) v = value(generator);
    result.emplace_back("dense random direction " + std::to_string(dense), std::move(d));
  }
  std::vector<std::size_t> elements{0};
  if (n > 1) elements.push_back(n - 1);
  if (n > 2) elements.push_back(1 + std::uniform_int_distribution<std::size_t>(0, n - 3)(generator));
  for (std::size_t element : elements) {
    std::vector<double> d(n, 0.0);
    d[element] = 1;
    result.emplace_back("element " + std::to_string(element), std::move(d));
  }
  return result;
}

}  // namespace

NamedTensors drawInputs(const OpExample& example) {
  NamedTensors inputs;
  uint64_t stream = 0;
  for (const auto& [name, draw] : example.inputs)
    inputs[name] = {draw.shape, draw.values(draw.shape, example.seed * 7919 + ++stream)};
  return inputs;
}

NamedTensors drawSeeds(const NamedTensors& outputs, uint64_t seed) {
  NamedTensors seeds;
  std::mt19937_64 generator(seed * 104729 + 17);
  std::uniform_real_distribution<float> value(-1, 1);
  for (const auto& [name, output] : outputs) {
    HostTensor& g = seeds[name];
    g.shape = output.shape;
    g.values.resize(output.values.size());
    for (float& v : g.values) v = value(generator);
  }
  return seeds;
}

OpResult runDirect(Context& context, const OpSpec& spec, const OpExample& example, const NamedTensors& inputs,
                   const NamedTensors* seeds) {
  TensorGuards* guards = context.tensorGuards();
  if (guards) guards->clear();
  Stream stream(context);
  Tape tape(stream);
  const std::vector<std::string> names = inputNames(spec);
  std::vector<Var> vars;
  for (const std::string& name : names) {
    auto given = inputs.find(name);
    vars.push_back(given == inputs.end() ? nullptr
                                         : variable(Tensor::fromHost(context, given->second.shape, given->second.values),
                                                    seeds != nullptr, name));
  }
  const std::vector<Var> outputs = spec.apply(tape, vars, resolveAttrs(spec, example.attrs));
  if (outputs.size() != spec.outputs.size())
    throw Error("op " + spec.name + " returned " + std::to_string(outputs.size()) + " outputs, its spec names " +
                std::to_string(spec.outputs.size()));
  if (seeds) {
    std::vector<std::pair<Var, Tensor>> seedTensors;
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      const HostTensor& g = seeds->at(spec.outputs[i]);
      seedTensors.emplace_back(outputs[i], Tensor::fromHost(context, g.shape, g.values));
    }
    tape.backward(seedTensors);
  }
  stream.submit();
  OpResult result;
  if (guards) result.guardViolations = guards->violations();
  for (std::size_t i = 0; i < outputs.size(); ++i) result.outputs[spec.outputs[i]] = download(outputs[i]->value);
  if (seeds)
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (!vars[i]) continue;
      result.gradients["grad_" + names[i]] =
          vars[i]->grad.defined()
              ? download(vars[i]->grad)
              : HostTensor{vars[i]->value.shape(), std::vector<float>(static_cast<std::size_t>(vars[i]->value.numel()), 0.0f)};
    }
  return result;
}

OpResult runThroughCli(const OpSpec& spec, const OpExample& example, const NamedTensors& inputs,
                       const NamedTensors* seeds, std::string* failure) {
  std::map<std::string, io::NpyArray> files;
  for (const auto& [name, tensor] : inputs) files[name] = io::NpyArray::fromFloats(tensor.shape, tensor.values);
  std::vector<std::string> wanted = spec.outputs;
  if (seeds) {
    for (const auto& [name, seed] : *seeds) files["grad_" + name] = io::NpyArray::fromFloats(seed.shape, seed.values);
    for (const auto& [name, tensor] : inputs) wanted.push_back("grad_" + name);
  }
  const OpRun run = runOpCommand(spec.name, files, wanted, attrList(example),
                                 example.noFloatAtomics ? "--no-float-atomics" : "");
  OpResult result;
  if (run.exitCode != 0) {
    if (failure) *failure = "exit status " + std::to_string(run.exitCode) + ": " + run.err;
    return result;
  }
  for (const auto& [name, array] : run.outputs)
    (name.starts_with("grad_") && !std::count(spec.outputs.begin(), spec.outputs.end(), name) ? result.gradients
                                                                                              : result.outputs)[name] =
        {array.shape, array.toFloat()};
  return result;
}

::testing::AssertionResult allFinite(const OpResult& result) {
  for (const NamedTensors* group : {&result.outputs, &result.gradients})
    for (const auto& [name, tensor] : *group) {
      std::size_t bad = 0, first = 0;
      for (std::size_t i = tensor.values.size(); i-- > 0;)
        if (!std::isfinite(tensor.values[i])) ++bad, first = i;
      if (bad)
        return ::testing::AssertionFailure() << name << " " << toString(tensor.shape) << ": " << bad
                                             << " elements not finite (NaN: never written), the first at flat index "
                                             << first << " = " << tensor.values[first];
    }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult guardsIntact(const OpResult& result) {
  if (result.guardViolations.empty()) return ::testing::AssertionSuccess();
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << "a kernel wrote past the end of a tensor:";
  for (const std::string& violation : result.guardViolations) failure << "\n  " << violation;
  return failure;
}

::testing::AssertionResult sameResults(const OpResult& expected, const OpResult& actual, double relative) {
  for (const auto& [group, expectedGroup, actualGroup] :
       {std::tuple{"output", &expected.outputs, &actual.outputs},
        std::tuple{"gradient", &expected.gradients, &actual.gradients}}) {
    if (expectedGroup->size() != actualGroup->size())
      return ::testing::AssertionFailure() << expectedGroup->size() << " " << group << "s expected, got "
                                           << actualGroup->size();
    for (const auto& [name, e] : *expectedGroup) {
      auto found = actualGroup->find(name);
      if (found == actualGroup->end()) return ::testing::AssertionFailure() << group << " " << name << " is missing";
      const HostTensor& a = found->second;
      if (a.shape != e.shape)
        return ::testing::AssertionFailure() << name << ": shape " << toString(a.shape) << ", expected "
                                             << toString(e.shape);
      double largest = 0;
      for (float v : e.values) largest = std::max(largest, static_cast<double>(std::abs(v)));
      const double allowed = relative * largest;
      std::size_t differ = 0, first = 0;
      for (std::size_t i = e.values.size(); i-- > 0;) {
        const bool same = relative == 0 ? std::memcmp(&e.values[i], &a.values[i], sizeof(float)) == 0
                                        : std::abs(static_cast<double>(e.values[i]) - a.values[i]) <= allowed;
        if (!same) ++differ, first = i;
      }
      if (differ) {
        std::ostringstream message;
        message.precision(9);
        message << name << " " << toString(e.shape) << ": " << differ << " elements differ ("
                << (relative == 0 ? std::string("bit for bit") : "beyond " + std::to_string(allowed))
                << "), the first at flat index " << first << ": " << a.values[first] << ", expected " << e.values[first];
        return ::testing::AssertionFailure() << message.str();
      }
    }
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult gradientsMatchDifferences(Context& context, const OpSpec& spec, const OpExample& example,
                                                     const NamedTensors& inputs, const NamedTensors& seeds,
                                                     const OpResult& withGradients) {
  const GradientCheck& check = example.gradient;
  std::ostringstream failures;
  failures.precision(9);
  int failed = 0;
  uint64_t probeSeed = example.seed * 31 + 5;
  for (const auto& [name, input] : inputs) {
    if (!example.inputs.at(name).differentiable) continue;
    const std::vector<float>& gradient = withGradients.gradients.at("grad_" + name).values;
    for (const auto& [probe, direction] : probes(input.values.size(), ++probeSeed)) {
      NamedTensors plus = inputs, minus = inputs;
      double analytic = 0;
      for (std::size_t i = 0; i < direction.size(); ++i) {
        if (direction[i] == 0) continue;
        float& p = plus[name].values[i];
        float& m = minus[name].values[i];
        p = static_cast<float>(p + check.step * direction[i]);
        m = static_cast<float>(m - check.step * direction[i]);
        analytic += static_cast<double>(gradient[i]) * (static_cast<double>(p) - m) / (2 * check.step);
      }
      const NamedTensors fPlus = runDirect(context, spec, example, plus, nullptr).outputs;
      const NamedTensors fMinus = runDirect(context, spec, example, minus, nullptr).outputs;
      const double numeric = (projected(fPlus, seeds) - projected(fMinus, seeds)) / (2 * check.step);
      const double floor = roundingOfDifference(fPlus, fMinus, seeds) / (2 * check.step);
      const double allowed = check.atol + check.rtol * std::max(std::abs(analytic), std::abs(numeric)) + floor;
      if (!(std::abs(analytic - numeric) <= allowed)) {
        ++failed;
        failures << "\n  grad_" << name << " " << toString(input.shape) << " along " << probe << ": backward "
                 << analytic << ", central difference " << numeric << " (step " << check.step << "), allowed "
                 << allowed << " (rounding floor " << floor << ")";
      }
    }
  }
  if (failed == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << failed << " probes disagree:" << failures.str();
}

}  // namespace smokesvd::testing
