#include "nets/diffusion/prediction.h"

#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::diffusion {

Prediction predictionFromName(const std::string& name, const std::string& where) {
  if (name == "epsilon") return Prediction::Noise;
  if (name == "v") return Prediction::Velocity;
  throw Error(where + ": 'prediction' must be \"epsilon\" or \"v\", not \"" + name + "\"");
}

std::string predictionName(Prediction prediction) { return prediction == Prediction::Noise ? "epsilon" : "v"; }

Var predictionTarget(Tape& tape, Prediction prediction, const Var& clean, const Var& noise, const StepFactorTensors& factors) {
  if (prediction == Prediction::Noise) return noise;
  return fn::sub(tape, fn::mulSample(tape, noise, factors.a), fn::mulSample(tape, clean, factors.b));
}

Var noiseFromPrediction(Tape& tape, Prediction prediction, const Var& noisy, const Var& output,
                        const StepFactorTensors& factors) {
  if (prediction == Prediction::Noise) return output;
  return fn::add(tape, fn::mulSample(tape, noisy, factors.b), fn::mulSample(tape, output, factors.a));
}

Var cleanFromPrediction(Tape& tape, Prediction prediction, const Var& noisy, const Var& output,
                        const StepFactorTensors& factors) {
  if (prediction == Prediction::Noise) return estimateClean(tape, noisy, output, factors);
  return fn::sub(tape, fn::mulSample(tape, noisy, factors.a), fn::mulSample(tape, output, factors.b));
}

}  // namespace smokesvd::diffusion
