#include "nets/modules/activation.h"

#include "nets/functional/activation.h"
#include "nets/functional/dropout.h"

namespace smokesvd::modules {

Var activate(Tape& tape, ActivationKind kind, const Var& x, float negativeSlope) {
  switch (kind) {
    case ActivationKind::ReLU: return fn::relu(tape, x);
    case ActivationKind::LeakyReLU: return fn::leakyRelu(tape, x, negativeSlope);
    case ActivationKind::SiLU: return fn::silu(tape, x);
    case ActivationKind::Sigmoid: return fn::sigmoid(tape, x);
    case ActivationKind::Tanh: return fn::tanh(tape, x);
  }
  return x;
}

Var Dropout::forward(Tape& tape, const Var& x) {
  if (passesThrough()) return x;
  return fn::dropout(tape, x, p_, (seed_ << 32) + calls_++, true);
}

}  // namespace smokesvd::modules
