// Adam and AdamW on the GPU with torch.optim.Adam / AdamW semantics (amsgrad, maximize and foreach
// variants aside). Per parameter p with gradient g, at step t (1, 2, ...), learning rate lr(t - 1):
//   Adam:  g += weightDecay p                      (L2 penalty through the gradient)
//   AdamW: p *= 1 - lr weightDecay                 (decoupled weight decay)
//   m = beta1 m + (1 - beta1) g,   v = beta2 v + (1 - beta2) g^2
//   p -= lr / (1 - beta1^t) * m / (sqrt(v) / sqrt(1 - beta2^t) + eps)
// eps is added to the bias-corrected sqrt(v), exactly where PyTorch adds it.
//
// The step counter t and the scalars of each step (scheduled lr, bias-corrected step size, decay
// factor) live in a small GPU tensor that a one-invocation kernel advances at the start of every
// recorded step (shaders/nn/optimizer_step.comp). So a training step recorded once (forward,
// backward, clipping, Adam) can be submitted again and again unchanged: nothing is written or read by
// the host per step. See docs/nn-training.md.
//
// The moments of the small parameters live in two flat tensors (flat_layout.h); a step gathers those
// parameters and their gradients into flat tensors of the same layout, updates them in one dispatch (one
// per run of parameters that have a gradient) and scatters the parameters back. Large parameters keep
// moments of their own and get a dispatch each.
#pragma once

#include <string>
#include <vector>

#include "nets/optim/flat_layout.h"
#include "nets/optim/grad_clip.h"
#include "nets/optim/parameters.h"
#include "nets/optim/schedule.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::optim {

struct AdamOptions {
  LrSchedule schedule = LrSchedule::constant(1e-3);
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-8;
  double weightDecay = 0.0;
  bool decoupledWeightDecay = false;  // false: Adam (L2 through the gradient); true: AdamW

  // torch.optim.AdamW's defaults: weight decay 0.01, decoupled.
  static AdamOptions adamW(LrSchedule schedule, double weightDecay = 0.01);
  void validate() const;  // throws Error naming the offending field
};

class Adam {
 public:
  static constexpr int64_t kMaxSteps = int64_t{1} << 24;  // the GPU counter is a float, exact up to here

  // The moments start at zero and the step counter at 0. Parameters must require a gradient.
  Adam(Context& context, NamedParameters parameters, AdamOptions options = {});

  // Records one step: the counter and scalars advance, then every parameter that has a gradient at
  // recording time is updated (those without one are skipped, as PyTorch skips a None grad). With
  // `clip`, the gradients are scaled by its factor (GradClip::record must be recorded before).
  void step(Stream& stream, const GradClip* clip = nullptr) const;

  // Steps taken so far (read back; the GPU holds the counter).
  int64_t steps() const;
  // Sets the counter, e.g. when resuming from a checkpoint; 0 <= steps <= kMaxSteps.
  void setSteps(int64_t steps);

  // Copies of the optimiser's state by name: "<parameter>.exp_avg" and "<parameter>.exp_avg_sq" per parameter.
  std::vector<std::pair<std::string, Tensor>> namedState() const;
  // Sets the state from tensors named and shaped as namedState() gives them (e.g. its copies, loaded).
  void restoreState(const std::vector<std::pair<std::string, Tensor>>& state);
  // [t, lr, lr / c1, sqrt(c2), 1 - lr weightDecay (AdamW) or 1, c1 = 1 - beta1^t, c2 = 1 - beta2^t, unused]
  const Tensor& scalars() const { return scalars_; }
  // The learning rate of the last step taken (read back).
  float lastLearningRate() const;
  const AdamOptions& options() const { return options_; }
  const NamedParameters& parameters() const { return parameters_; }

 private:
  AdamOptions options_;
  NamedParameters parameters_;
  std::vector<Tensor> values_;  // the parameters' values, in order
  FlatLayout layout_;
  FlatState expAvg_, expAvgSq_;
  Tensor gatheredValues_, gatheredGradients_;  // what each step gathers, updates and scatters back
  Tensor scalars_;
  Tensor noClip_;  // [0, 1]: the factor 1 when there is no clipping
};

}  // namespace smokesvd::optim
