// An exponential moving average of weights on the GPU, as kept for diffusion models:
//   shadow = decay shadow + (1 - decay) param   (computed as torch's lerp: shadow + (1 - decay)(param - shadow))
// The shadows start as copies of the parameters and carry the parameters' names, so they can be saved
// as a weight file that loads into the same model (here or in PyTorch).
#pragma once

#include <vector>

#include "nets/optim/parameters.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::optim {

class Ema {
 public:
  Ema(Context& context, NamedParameters parameters, double decay);

  // Records one update of every shadow (typically right after the optimiser step).
  void update(Stream& stream) const;
  // Records shadow -> parameter copies (to evaluate or export the averaged model).
  void copyToParameters(Stream& stream) const;

  // The shadows under the parameters' names.
  std::vector<std::pair<std::string, Tensor>> namedShadows() const;
  double decay() const { return decay_; }

 private:
  NamedParameters parameters_;
  std::vector<Tensor> shadows_;
  double decay_;
};

}  // namespace smokesvd::optim
