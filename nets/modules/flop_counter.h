// Counts the arithmetic of the convolutions and linear layers that forward passes record while a
// counter is alive, for cost reports (GFLOP per forward). A multiply-add is two FLOPs:
//   convolution  2 * output elements * input channels * kernel elements
//   linear       2 * output elements * input features
// Everything else a network does (activations, norms, resampling) is memory-bound and not counted.
//
//   modules::FlopCounter counter;          // counts on this thread while alive; counters may nest
//   net.forward(tape, x);
//   double gflop = counter.flops() * 1e-9;
#pragma once

namespace smokesvd::modules {

class FlopCounter {
 public:
  FlopCounter();
  ~FlopCounter();
  FlopCounter(const FlopCounter&) = delete;
  FlopCounter& operator=(const FlopCounter&) = delete;

  double flops() const { return flops_; }

  // Adds to every live counter on this thread (Conv and Linear call it from forward).
  static void count(double flops);

 private:
  double flops_ = 0;
  FlopCounter* outer_ = nullptr;
};

}  // namespace smokesvd::modules
