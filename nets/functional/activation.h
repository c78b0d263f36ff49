// Differentiable pointwise activations (autograd wrappers of nets/ops/activation.h), any shape:
//
//   Var relu(Tape& tape, const Var& x);                                  // max(x, 0)
//   Var leakyRelu(Tape& tape, const Var& x, float negativeSlope = 0.01f); // x > 0 ? x : slope x
//   Var silu(Tape& tape, const Var& x);                                  // x sigmoid(x)
//   Var sigmoid(Tape& tape, const Var& x);                               // 1 / (1 + e^-x)
//   Var tanh(Tape& tape, const Var& x);                                  // tanh(x)
//
// PyTorch: F.relu, F.leaky_relu(x, negative_slope), F.silu, torch.sigmoid, torch.tanh. At x = 0 the
// ReLU and LeakyReLU gradients take the x <= 0 branch (0 and slope), as PyTorch's.
// Registered for `smokesvd op` as relu, leaky_relu (attr negative_slope), silu, sigmoid, tanh.
#pragma once

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var relu(Tape& tape, const Var& x);
Var leakyRelu(Tape& tape, const Var& x, float negativeSlope = 0.01f);
Var silu(Tape& tape, const Var& x);
Var sigmoid(Tape& tape, const Var& x);
Var tanh(Tape& tape, const Var& x);

}  // namespace smokesvd::fn
