#include "nets/modules/linear.h"

#include "nets/functional/linear.h"
#include "nets/modules/flop_counter.h"

namespace smokesvd::modules {

Linear::Linear(Context& context, int64_t inFeatures, int64_t outFeatures, bool bias, WeightInit init) {
  weight_ = addParameter(context, "weight", {outFeatures, inFeatures}, Init::weight(init, inFeatures));
  if (bias) bias_ = addParameter(context, "bias", {outFeatures}, Init::bias(init, inFeatures));
}

Var Linear::forward(Tape& tape, const Var& x) {
  Var y = fn::linear(tape, x, weight_, bias_);
  countLayer(2.0 * static_cast<double>(y->value.numel()) * static_cast<double>(weight_->value.size(1)), y, {x}, weight_);
  return y;
}

}  // namespace smokesvd::modules
