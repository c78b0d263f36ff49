// Elementwise add/sub/mul/div with NumPy broadcasting (shapes aligned at their last axis; an axis of
// size 1 or a missing leading axis is repeated), and the reduction of a gradient back to an operand.
// Typical: per-channel vectors [1, C, 1, 1] or [N, C, 1, 1] and per-sample vectors [N, 1, 1, 1]
// against N,C,H,W (or N,C,D,H,W).
//
// Supported: patterns whose axes, after dropping size-1 output axes and merging neighbours that
// broadcast alike, form at most 4 runs (every case above). Anything else is an Error naming the shapes.
#pragma once

#include <vector>

#include "nets/ops/elementwise.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// The broadcast shape of a and b (NumPy rules); Error naming `op` and both shapes if incompatible.
Shape broadcastShape(const char* op, const Shape& a, const Shape& b);
// Axes of `output` along which `operand` (which broadcasts to output) is repeated: summing a gradient of
// `output` over them gives the gradient of `operand` (same number of elements).
std::vector<int> broadcastAxes(const Shape& operand, const Shape& output);

// y = a op b, y with broadcastShape(a, b).
void broadcastBinary(Stream& stream, BinaryOp op, const Tensor& a, const Tensor& b, const Tensor& y);
// y = x repeated to y's shape (x must broadcast to it).
void expand(Stream& stream, const Tensor& x, const Tensor& y);

// (multiplier, shift) for dividing by d in a shader without integer division (shaders/nn/broadcast_index.glsl).
struct FastDivisor {
  uint32_t multiplier = 0;
  uint32_t shift = 0;
};
FastDivisor fastDivisor(uint32_t d);

}  // namespace smokesvd::ops
