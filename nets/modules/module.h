// A small module system in the shape of torch.nn.Module: a module owns named parameters and named child
// modules, and its parameters' dotted names ("down.0.block.1.conv1.weight") are exactly the keys PyTorch's
// state_dict() gives the equivalent torch.nn tree, in the same order (a module's own parameters in
// registration order, then each child's, depth first). So weight files move between the two unchanged
// (nets/modules/weights.h).
//
// Parameters are Variables that require a gradient; a module's forward records fn:: ops on a Tape. A
// freshly built module holds zeros: initialize(seed) on the root draws every parameter from its rule
// (nets/modules/init.h), or weights are loaded from a file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "nets/autograd/tape.h"
#include "nets/modules/init.h"
#include "nets/optim/parameters.h"

namespace smokesvd::modules {

class Module {
 public:
  Module() = default;
  virtual ~Module() = default;
  Module(const Module&) = delete;
  Module& operator=(const Module&) = delete;

  // Every parameter under this module with its dotted name relative to it, in state_dict order.
  NamedParameters namedParameters() const;
  int64_t parameterCount() const;  // total number of values
  // Draws every parameter under this module from its rule, seeded by (seed, dotted name relative to here).
  void initialize(uint64_t seed);
  // Training mode (dropout active) or evaluation mode, for this module and every module under it.
  void setTraining(bool training);
  bool training() const { return training_; }

  const std::vector<std::pair<std::string, std::shared_ptr<Module>>>& children() const { return children_; }

 protected:
  // A parameter named `name` (no dots) of the given shape, zero until initialised.
  Var addParameter(Context& context, const std::string& name, Shape shape, Init init);
  // A child module named `name`; its parameters are named "<name>.<their name>".
  template <typename M>
  std::shared_ptr<M> addChild(const std::string& name, std::shared_ptr<M> child) {
    addChildModule(name, child);
    return child;
  }

 private:
  struct Parameter {
    std::string name;
    Var value;
    Init init;
  };
  void addChildModule(const std::string& name, std::shared_ptr<Module> child);
  void collect(const std::string& prefix, NamedParameters& out) const;
  void initializeUnder(const std::string& prefix, uint64_t seed);
  void checkNewName(const std::string& name) const;

  std::vector<Parameter> parameters_;
  std::vector<std::pair<std::string, std::shared_ptr<Module>>> children_;
  bool training_ = true;
};

// A module with one input and one output, the kind Sequential chains.
class UnaryModule : public Module {
 public:
  virtual Var forward(Tape& tape, const Var& x) = 0;
};

// torch.nn.Sequential: children named "0", "1", ... applied in order.
class Sequential : public UnaryModule {
 public:
  Sequential() = default;
  explicit Sequential(std::vector<std::shared_ptr<UnaryModule>> modules);
  // Appends a module (named by its position) and returns it.
  template <typename M>
  std::shared_ptr<M> add(std::shared_ptr<M> module) {
    layers_.push_back(module);
    return addChild(std::to_string(layers_.size() - 1), module);
  }
  Var forward(Tape& tape, const Var& x) override;
  std::size_t size() const { return layers_.size(); }

 private:
  std::vector<std::shared_ptr<UnaryModule>> layers_;
};

// torch.nn.ModuleList: children named "0", "1", ... with no forward of its own.
class ModuleList : public Module {
 public:
  template <typename M>
  std::shared_ptr<M> add(std::shared_ptr<M> module) {
    items_.push_back(module);
    return addChild(std::to_string(items_.size() - 1), module);
  }
  std::size_t size() const { return items_.size(); }
  const std::shared_ptr<Module>& operator[](std::size_t i) const { return items_.at(i); }

 private:
  std::vector<std::shared_ptr<Module>> items_;
};

}  // namespace smokesvd::modules
