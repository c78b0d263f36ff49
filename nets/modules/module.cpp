#include "nets/modules/module.h"

#include "runtime/error.h"

namespace smokesvd::modules {

void Module::checkNewName(const std::string& name) const {
  if (name.empty() || name.find('.') != std::string::npos)
    throw Error("module: '" + name + "' cannot name a parameter or child (empty or containing '.')");
  for (const Parameter& parameter : parameters_)
    if (parameter.name == name) throw Error("module: the name '" + name + "' is already a parameter");
  for (const auto& [childName, child] : children_)
    if (childName == name) throw Error("module: the name '" + name + "' is already a child module");
}

Var Module::addParameter(Context& context, const std::string& name, Shape shape, Init init) {
  checkNewName(name);
  Tensor value(context, std::move(shape));
  value.upload(std::vector<float>(static_cast<std::size_t>(value.numel()), 0.0f));
  Var parameter = variable(value, true, name);
  parameters_.push_back({name, parameter, init});
  return parameter;
}

void Module::addChildModule(const std::string& name, std::shared_ptr<Module> child) {
  checkNewName(name);
  if (!child) throw Error("module: child '" + name + "' is null");
  child->setTraining(training_);
  children_.emplace_back(name, std::move(child));
}

void Module::collect(const std::string& prefix, NamedParameters& out) const {
  for (const Parameter& parameter : parameters_) out.emplace_back(prefix + parameter.name, parameter.value);
  for (const auto& [name, child] : children_) child->collect(prefix + name + ".", out);
}

NamedParameters Module::namedParameters() const {
  NamedParameters named;
  collect("", named);
  return named;
}

int64_t Module::parameterCount() const {
  int64_t count = 0;
  for (const auto& [name, parameter] : namedParameters()) count += parameter->value.numel();
  return count;
}

void Module::initializeUnder(const std::string& prefix, uint64_t seed) {
  for (const Parameter& parameter : parameters_) {
    const std::string name = prefix + parameter.name;
    parameter.value->value.upload(
        drawValues(parameter.init, static_cast<std::size_t>(parameter.value->value.numel()), seed, name));
  }
  for (const auto& [name, child] : children_) child->initializeUnder(prefix + name + ".", seed);
}

void Module::initialize(uint64_t seed) { initializeUnder("", seed); }

void Module::setTraining(bool training) {
  training_ = training;
  for (const auto& [name, child] : children_) child->setTraining(training);
}

Sequential::Sequential(std::vector<std::shared_ptr<UnaryModule>> modules) {
  for (auto& module : modules) add(std::move(module));
}

Var Sequential::forward(Tape& tape, const Var& x) {
  Var y = x;
  for (const auto& layer : layers_) y = layer->forward(tape, y);
  return y;
}

}  // namespace smokesvd::modules
