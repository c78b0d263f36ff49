#include "nets/autograd/tape.h"

#include <algorithm>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd {

Var Tape::output(Tensor value, std::initializer_list<Var> inputs) const {
  const bool needsGrad =
      gradEnabled_ && std::any_of(inputs.begin(), inputs.end(), [](const Var& v) { return v && v->requiresGrad; });
  return variable(std::move(value), needsGrad);
}

void Tape::record(std::vector<Var> outputs, std::function<void(Tape&)> backward) {
  if (!gradEnabled_) return;
  entries_.push_back({std::move(outputs), std::move(backward)});
}

Tensor Tape::grad(const Var& output) {
  if (!output->grad.defined()) {
    output->grad = Tensor(context(), output->value.shape());
    ops::fill(stream_, output->grad, 0.0f);
  }
  return output->grad;
}

void Tape::accumulate(const Var& input, const Tensor& gradient) {
  if (!input || !input->requiresGrad) return;
  if (gradient.shape() != input->value.shape())
    throw Error("autograd: gradient of shape " + toString(gradient.shape()) + " for a value of shape " +
                toString(input->value.shape()));
  if (!input->grad.defined()) {
    input->grad = gradient;
    return;
  }
  Tensor sum(context(), input->value.shape());
  ops::add(stream_, input->grad, gradient, sum);
  input->grad = sum;
}

void Tape::accumulateWriting(const Var& input,
                             const std::function<void(const Tensor* sofar, const Tensor& sum)>& write) {
  if (!input || !input->requiresGrad) return;
  Tensor sum(context(), input->value.shape());
  write(input->grad.defined() ? &input->grad : nullptr, sum);
  input->grad = sum;
}

void Tape::backward(const Var& loss) {
  Tensor ones(context(), loss->value.shape());
  ops::fill(stream_, ones, 1.0f);
  backward({{loss, ones}});
}

void Tape::backward(const std::vector<std::pair<Var, Tensor>>& seeds) {
  for (const auto& [output, seed] : seeds) {
    if (!output->requiresGrad) throw Error("autograd: backward from a value that does not require a gradient");
    accumulate(output, seed);
  }
  // Each op is dropped once its backward is recorded: the activations its closure kept and the gradients
  // only it read go with it, so a recording stream can reuse their memory for the ops still to come.
  while (!entries_.empty()) {
    Entry entry = std::move(entries_.back());
    entries_.pop_back();
    const bool reached = std::any_of(entry.outputs.begin(), entry.outputs.end(),
                                     [](const Var& output) { return output->grad.defined(); });
    if (reached) entry.backward(*this);
  }
}

}  // namespace smokesvd
