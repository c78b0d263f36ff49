// torch.nn.Linear: y = x W^T + b over the last axis; parameters "weight" [out, in] and "bias" [out].
#pragma once

#include "nets/modules/module.h"

namespace smokesvd::modules {

class Linear : public UnaryModule {
 public:
  Linear(Context& context, int64_t inFeatures, int64_t outFeatures, bool bias = true, WeightInit init = WeightInit::He);
  Var forward(Tape& tape, const Var& x) override;
  const Var& weight() const { return weight_; }
  const Var& bias() const { return bias_; }  // nullptr without bias

 private:
  Var weight_;
  Var bias_;
};

}  // namespace smokesvd::modules
