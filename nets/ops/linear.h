// Matrix products and the linear layer y = x W^T + b (PyTorch layout: W [out, in], x [..., in]).
// One register-blocked kernel (shaders/nn/matmul.comp) serves the forward pass and both backward
// passes by reading its operands transposed or not.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// c [M, N] = op(a) op(b) (+ bias [N]) with op(a) = a for a [M, K] or a^T for a [K, M] (transposeA), and
// op(b) = b for b [K, N] or b^T for b [N, K] (transposeB). a, b and c are rank 2; bias has N elements.
void matmul(Stream& stream, const Tensor& a, bool transposeA, const Tensor& b, bool transposeB, const Tensor* bias,
            const Tensor& c);

// y [..., out] = x [..., in] W^T + bias, for W [out, in] and bias [out] (or none).
void linearForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& y);
// gx [..., in] = gy [..., out] W
void linearBackwardInput(Stream& stream, const Tensor& gy, const Tensor& w, const Tensor& gx);
// gw [out, in] = gy^T x, summed over every leading index of x and gy
void linearBackwardWeight(Stream& stream, const Tensor& gy, const Tensor& x, const Tensor& gw);
// gb [out] = gy summed over every leading index
void linearBackwardBias(Stream& stream, const Tensor& gy, const Tensor& gb);

}  // namespace smokesvd::ops
