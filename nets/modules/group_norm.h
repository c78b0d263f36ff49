// torch.nn.GroupNorm(groups, channels, eps, affine): normalises each group of channels of each sample
// over the group's channels and positions; parameters "weight" [C] (init 1) and "bias" [C] (init 0).
#pragma once

#include "nets/modules/module.h"

namespace smokesvd::modules {

class GroupNorm : public UnaryModule {
 public:
  GroupNorm(Context& context, int groups, int64_t channels, float eps = 1e-5f, bool affine = true);
  Var forward(Tape& tape, const Var& x) override;
  // F.silu(forward(x)) in one pass (fn::groupNormSilu)
  Var forwardThenSilu(Tape& tape, const Var& x);
  int groups() const { return groups_; }
  float eps() const { return eps_; }
  const Var& weight() const { return weight_; }  // nullptr without affine
  const Var& bias() const { return bias_; }

 private:
  int groups_;
  float eps_;
  Var weight_;
  Var bias_;
};

}  // namespace smokesvd::modules
