// Parameters by name: the dotted names of a module tree (nets/modules), which the optimisers, the EMA
// and the weight files use to tell parameters apart.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "nets/autograd/variable.h"

namespace smokesvd {

using NamedParameters = std::vector<std::pair<std::string, Var>>;

// Forgets every parameter's gradient (torch's zero_grad(set_to_none=True)), so the next backward pass
// starts fresh. Needed when each step is recorded anew; a recording submitted again recomputes its
// gradients from scratch and needs nothing.
inline void clearGradients(const NamedParameters& parameters) {
  for (const auto& [name, parameter] : parameters) parameter->grad = Tensor{};
}

}  // namespace smokesvd
