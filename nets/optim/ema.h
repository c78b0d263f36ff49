// An exponential moving average of weights on the GPU, as kept for diffusion models:
//   shadow = decay shadow + (1 - decay) param   (computed as torch's lerp: shadow + (1 - decay)(param - shadow))
// The shadows start as copies of the parameters and carry the parameters' names, so they can be saved
// as a weight file that loads into the same model (here or in PyTorch). The small parameters' shadows live
// in one flat tensor (flat_layout.h): an update gathers those parameters into another and averages them in
// one dispatch; large parameters have shadows and a dispatch of their own.
#pragma once

#include <vector>

#include "nets/optim/flat_layout.h"
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

  // Copies of the shadows under the parameters' names.
  std::vector<std::pair<std::string, Tensor>> namedShadows() const;
  // Sets the shadows from tensors named and shaped as namedShadows() gives them.
  void restoreShadows(const std::vector<std::pair<std::string, Tensor>>& shadows);
  double decay() const { return decay_; }

 private:
  NamedParameters parameters_;
  std::vector<Tensor> values_;  // the parameters' values, in order
  FlatLayout layout_;
  FlatState shadows_;
  Tensor gathered_;  // the parameters each update gathers
  double decay_;
};

}  // namespace smokesvd::optim
