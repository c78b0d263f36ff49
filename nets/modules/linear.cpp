#include "nets/modules/linear.h"

#include "nets/functional/linear.h"

namespace smokesvd::modules {

Linear::Linear(Context& context, int64_t inFeatures, int64_t outFeatures, bool bias, WeightInit init) {
  weight_ = addParameter(context, "weight", {outFeatures, inFeatures}, Init::weight(init, inFeatures));
  if (bias) bias_ = addParameter(context, "bias", {outFeatures}, Init::bias(init, inFeatures));
}

Var Linear::forward(Tape& tape, const Var& x) { return fn::linear(tape, x, weight_, bias_); }

}  // namespace smokesvd::modules
