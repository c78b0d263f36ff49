// Pointwise activation kernels (shaders/nn/activation.comp) on float32 tensors of any shape.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

enum class Activation { Relu = 0, LeakyRelu = 1, Silu = 2, Sigmoid = 3, Tanh = 4 };

// y = f(x). negativeSlope is used by LeakyRelu only.
void activationForward(Stream& stream, Activation activation, float negativeSlope, const Tensor& x, const Tensor& y);
// gx = gy * f'(x) (ReLU and LeakyReLU take the x <= 0 branch at x = 0, as PyTorch).
void activationBackward(Stream& stream, Activation activation, float negativeSlope, const Tensor& x,
                        const Tensor& gy, const Tensor& gx);

}  // namespace smokesvd::ops
