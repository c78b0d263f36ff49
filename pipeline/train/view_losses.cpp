#include "pipeline/train/view_losses.h"

#include <algorithm>
#include <cmath>

#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "runtime/error.h"

namespace smokesvd::train {

Var weightedViewMse(Tape& tape, const Var& a, const Var& b, const Var& sqrtWeights) {
  const Var scaled = fn::mulSample(tape, fn::sub(tape, a, b), sqrtWeights);
  Tensor zeros = Tensor::fromHost(tape.context(), scaled->value.shape(),
                                  std::vector<float>(static_cast<std::size_t>(scaled->value.numel()), 0.0f));
  return fn::scale(tape, fn::mseLoss(tape, scaled, variable(zeros)), static_cast<float>(a->value.size(0)));
}

double psnr(std::span<const float> a, std::span<const float> b) {
  if (a.size() != b.size() || a.empty()) throw Error("psnr: images of different sizes");
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = static_cast<double>(a[i]) - b[i];
    sum += d * d;
  }
  const double mse = sum / static_cast<double>(a.size());
  return mse > 0 ? std::min(100.0, -10.0 * std::log10(mse)) : 100.0;
}

}  // namespace smokesvd::train
