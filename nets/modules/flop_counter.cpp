#include "nets/modules/flop_counter.h"

namespace smokesvd::modules {
namespace {
thread_local FlopCounter* innermost = nullptr;
}  // namespace

FlopCounter::FlopCounter() : outer_(innermost) { innermost = this; }

FlopCounter::~FlopCounter() { innermost = outer_; }

void FlopCounter::count(double flops) {
  for (FlopCounter* counter = innermost; counter != nullptr; counter = counter->outer_) counter->flops_ += flops;
}

}  // namespace smokesvd::modules
