// Counts the arithmetic of the convolutions and linear layers that forward passes record while a
// counter is alive, for cost reports (GFLOP per forward, per training step). A multiply-add is two FLOPs:
//   convolution  F = 2 * output elements * input channels * kernel elements
//   linear       F = 2 * output elements * input features
// and a layer whose output needs a gradient adds F to the backward FLOPs for each of its input and its
// weight that needs one (the backward-input and backward-weight passes each cost as much as the forward).
// Everything else a network does (activations, norms, resampling) is memory-bound and not counted.
//
//   modules::FlopCounter counter;          // counts on this thread while alive; counters may nest
//   net.forward(tape, x);
//   double gflop = counter.flops() * 1e-9;
#pragma once

#include <vector>

#include "nets/autograd/variable.h"

namespace smokesvd::modules {

class FlopCounter {
 public:
  FlopCounter();
  ~FlopCounter();
  FlopCounter(const FlopCounter&) = delete;
  FlopCounter& operator=(const FlopCounter&) = delete;

  double flops() const { return flops_; }
  double backwardFlops() const { return backwardFlops_; }
  // Forward and backward FLOPs of the layers whose weights are trained (need a gradient).
  double trainedFlops() const { return trainedFlops_; }

  // Adds a layer's forward FLOPs, and `backwardPasses` times as many backward FLOPs, to every live
  // counter on this thread (Conv and Linear call it from forward).
  static void count(double flops, int backwardPasses = 0, bool trained = false);

 private:
  double flops_ = 0;
  double backwardFlops_ = 0;
  double trainedFlops_ = 0;
  FlopCounter* outer_ = nullptr;
};

// Counts a layer of `flops` forward FLOPs with output y: the backward passes it records, one to its inputs
// and one to its weight, each where a gradient is needed (none when y needs none: a frozen layer on inputs
// that need none, or NoGrad), and as the trained network's when its weight needs a gradient.
void countLayer(double flops, const Var& y, const std::vector<Var>& inputs, const Var& weight);

}  // namespace smokesvd::modules
