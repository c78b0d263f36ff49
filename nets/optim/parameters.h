// Parameters by name: the dotted names of a module tree (nets/modules), which the optimisers, the EMA
// and the weight files use to tell parameters apart.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "nets/autograd/variable.h"

namespace smokesvd {

using NamedParameters = std::vector<std::pair<std::string, Var>>;

}  // namespace smokesvd
