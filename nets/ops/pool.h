// Max and average pooling with kernel 2, stride 2, no padding and ceil mode (shaders/nn/pool.comp), on
// N,C,H,W and N,C,D,H,W float32 tensors of any size >= 1: PyTorch's max_pool{2,3}d / avg_pool{2,3}d with
// kernel_size=2, stride=2, ceil_mode=True. A window clipped by an odd size averages over its clipped
// size; max-pool picks (and routes gradients to) the first maximum of a window in (z, y, x) order.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

enum class PoolKind { Average = 0, Max = 1 };

// The output shape: every spatial size s becomes ceil(s / 2). Throws Error unless x is 4D or 5D.
Shape pooledShape(const Shape& x);

void poolForward(Stream& stream, PoolKind kind, const Tensor& x, const Tensor& y);
// gx from gy; max-pool reads x to find each window's maximum, average pooling does not read x.
void poolBackward(Stream& stream, PoolKind kind, const Tensor& x, const Tensor& gy, const Tensor& gx);

}  // namespace smokesvd::ops
