#include "nets/diffusion/forward_process.h"

#include <cmath>

#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"

namespace smokesvd::diffusion {

StepFactors stepFactors(const NoiseSchedule& schedule, std::span<const int> steps) {
  StepFactors f;
  for (const int step : steps) {
    const double abar = schedule.alphaBar(step);
    const double a = std::sqrt(abar), b = std::sqrt(1.0 - abar);
    f.a.push_back(static_cast<float>(a));
    f.b.push_back(static_cast<float>(b));
    f.inverseA.push_back(static_cast<float>(1.0 / a));
    f.bOverA.push_back(static_cast<float>(b / a));
  }
  return f;
}

StepFactorTensors::StepFactorTensors(Context& context, int64_t samples)
    : a(variable(Tensor(context, {samples}))), b(variable(Tensor(context, {samples}))),
      inverseA(variable(Tensor(context, {samples}))), bOverA(variable(Tensor(context, {samples}))) {}

void StepFactorTensors::upload(const StepFactors& factors) const {
  a->value.upload(factors.a);
  b->value.upload(factors.b);
  inverseA->value.upload(factors.inverseA);
  bOverA->value.upload(factors.bOverA);
}

Var addNoise(Tape& tape, const Var& clean, const Var& noise, const StepFactorTensors& factors) {
  return fn::add(tape, fn::mulSample(tape, clean, factors.a), fn::mulSample(tape, noise, factors.b));
}

Var estimateClean(Tape& tape, const Var& noisy, const Var& predictedNoise, const StepFactorTensors& factors) {
  return fn::sub(tape, fn::mulSample(tape, noisy, factors.inverseA), fn::mulSample(tape, predictedNoise, factors.bOverA));
}

}  // namespace smokesvd::diffusion
