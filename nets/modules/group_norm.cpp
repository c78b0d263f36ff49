#include "nets/modules/group_norm.h"

#include "nets/functional/group_norm.h"
#include "runtime/error.h"

namespace smokesvd::modules {

GroupNorm::GroupNorm(Context& context, int groups, int64_t channels, float eps, bool affine)
    : groups_(groups), eps_(eps) {
  if (groups <= 0 || channels % groups != 0)
    throw Error("GroupNorm: " + std::to_string(groups) + " groups do not divide " + std::to_string(channels) +
                " channels");
  if (affine) {
    weight_ = addParameter(context, "weight", {channels}, Init::constant(1.0));
    bias_ = addParameter(context, "bias", {channels}, Init::constant(0.0));
  }
}

Var GroupNorm::forward(Tape& tape, const Var& x) { return fn::groupNorm(tape, x, weight_, bias_, groups_, eps_); }

Var GroupNorm::forwardThenSilu(Tape& tape, const Var& x) {
  return fn::groupNormSilu(tape, x, weight_, bias_, groups_, eps_);
}

}  // namespace smokesvd::modules
