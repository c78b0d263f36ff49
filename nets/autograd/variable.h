// A value in a differentiable computation: a tensor, the gradient a backward pass accumulated for it,
// and whether gradients flow to it. Parameters are Variables with requiresGrad = true.
#pragma once

#include <memory>
#include <string>

#include "runtime/tensor.h"

namespace smokesvd {

struct Variable {
  Tensor value;
  Tensor grad;  // undefined until a backward pass reaches this variable
  bool requiresGrad = false;
  std::string name;
};

using Var = std::shared_ptr<Variable>;

inline Var variable(Tensor value, bool requiresGrad = false, std::string name = {}) {
  return std::make_shared<Variable>(Variable{std::move(value), Tensor{}, requiresGrad, std::move(name)});
}

}  // namespace smokesvd
