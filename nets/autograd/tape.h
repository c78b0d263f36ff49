// Reverse-mode automatic differentiation over GPU kernels.
//
// Ops record their forward kernels into the tape's Stream and, when an output needs a gradient, a
// backward closure. Tape::backward seeds the loss gradient and runs the closures in reverse order; each
// reads its outputs' gradients (Tape::grad) and adds into its inputs' (Tape::accumulate). Nothing is
// read back to the host, so a whole training step (forward, backward, optimiser) is one submit.
#pragma once

#include <functional>
#include <initializer_list>
#include <utility>
#include <vector>

#include "nets/autograd/variable.h"
#include "runtime/stream.h"

namespace smokesvd {

class Tape {
 public:
  explicit Tape(Stream& stream) : stream_(stream) {}
  Tape(const Tape&) = delete;
  Tape& operator=(const Tape&) = delete;

  Stream& stream() const { return stream_; }
  Context& context() const { return stream_.context(); }
  bool gradEnabled() const { return gradEnabled_; }

  // A new op output; it requires grad when grad is enabled and any input requires grad.
  Var output(Tensor value, std::initializer_list<Var> inputs) const;
  // Registers the backward of an op whose outputs are `outputs`. It runs only if one of them got a gradient.
  void record(std::vector<Var> outputs, std::function<void(Tape&)> backward);

  // Inside a backward closure: the upstream gradient of an output (zeros if none reached it).
  Tensor grad(const Var& output);
  // Inside a backward closure: input->grad += gradient; nothing if the input needs no gradient. The
  // given tensor is never written: it becomes the gradient, or a fresh sum replaces the gradient.
  void accumulate(const Var& input, const Tensor& gradient);
  // Inside a backward closure: input->grad += this op's contribution, written by `write(sofar, sum)` into a
  // fresh tensor `sum` of the input's shape as sofar + contribution (sofar: the gradient so far, nullptr if
  // none), so a kernel adds it as it writes instead of a separate sum. Nothing if the input needs no gradient.
  void accumulateWriting(const Var& input, const std::function<void(const Tensor* sofar, const Tensor& sum)>& write);

  // Runs recorded backwards in reverse order, seeding d loss / d loss = 1 everywhere in `loss`, and
  // forgets each op once its backward has run (the tape is empty afterwards).
  void backward(const Var& loss);
  // The same with given upstream gradients for any outputs.
  void backward(const std::vector<std::pair<Var, Tensor>>& seeds);

  // Forgets every recorded op (and the activations they kept alive).
  void clear() { entries_.clear(); }
  std::size_t recordedOps() const { return entries_.size(); }

 private:
  friend class NoGrad;
  struct Entry {
    std::vector<Var> outputs;
    std::function<void(Tape&)> backward;
  };
  Stream& stream_;
  bool gradEnabled_ = true;
  std::vector<Entry> entries_;
};

// Inference: ops under a NoGrad scope record no backward and their outputs need no gradient.
class NoGrad {
 public:
  explicit NoGrad(Tape& tape) : tape_(tape), previous_(tape.gradEnabled_) { tape.gradEnabled_ = false; }
  ~NoGrad() { tape_.gradEnabled_ = previous_; }
  NoGrad(const NoGrad&) = delete;
  NoGrad& operator=(const NoGrad&) = delete;

 private:
  Tape& tape_;
  bool previous_;
};

}  // namespace smokesvd
