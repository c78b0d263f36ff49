// Differentiable elementwise ops on Variables of equal shape (autograd wrappers of nets/ops/elementwise.h).
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var add(Tape& tape, const Var& a, const Var& b);  // y = a + b
Var sub(Tape& tape, const Var& a, const Var& b);  // y = a - b
Var mul(Tape& tape, const Var& a, const Var& b);  // y = a * b
Var scale(Tape& tape, const Var& x, float alpha); // y = alpha * x

}  // namespace smokesvd::fn
