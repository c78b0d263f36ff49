#include "nets/modules/flop_counter.h"

namespace smokesvd::modules {
namespace {
thread_local FlopCounter* innermost = nullptr;
}  // namespace

FlopCounter::FlopCounter() : outer_(innermost) { innermost = this; }

FlopCounter::~FlopCounter() { innermost = outer_; }

void FlopCounter::count(double flops, int backwardPasses, bool trained) {
  for (FlopCounter* counter = innermost; counter != nullptr; counter = counter->outer_) {
    counter->flops_ += flops;
    counter->backwardFlops_ += backwardPasses * flops;
    if (trained) counter->trainedFlops_ += (1 + backwardPasses) * flops;
  }
}

void countLayer(double flops, const Var& y, const std::vector<Var>& inputs, const Var& weight) {
  bool input = false;
  for (const Var& x : inputs) input = input || x->requiresGrad;
  const int backwardPasses = y->requiresGrad ? (input ? 1 : 0) + (weight->requiresGrad ? 1 : 0) : 0;
  FlopCounter::count(flops, backwardPasses, weight->requiresGrad);
}

}  // namespace smokesvd::modules
