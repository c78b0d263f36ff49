// Shapes of a convolution in the 3D form every convolution kernel works in (2D runs with depth 1),
// validated once, and the phase decomposition that turns a strided transposed convolution into
// stride-1 direct convolutions.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "nets/ops/conv.h"

namespace smokesvd::ops::conv {

using Int3 = std::array<int64_t, 3>;  // along z, y, x

struct ConvGeometry {
  int rank = 5;              // of the tensors: 4 (2D) or 5 (3D)
  int64_t batch = 0;         // N
  int64_t inChannels = 0;    // C
  int64_t outChannels = 0;   // K
  Int3 input{};              // D, H, W
  Int3 kernel{};             // KD, KH, KW
  Int3 output{};             // Do, Ho, Wo
  int stride = 1;            // along every axis (irrelevant along z in 2D, where Do = 1)
  Int3 padding{};            // along z, y, x (0 along z in 2D)
  Shape inputShape() const;
  Shape outputShape() const;
  Shape weightShape() const;  // conv layout [K, C, k...]
};

// The geometry of conv(x, w). Throws Error naming `op` unless x is [N, C, (D,) H, W], w is
// [K, C, (kD,) kH, kW] of the same rank, stride >= 1, padding >= 0 and the output is not empty.
ConvGeometry convGeometry(const char* op, const Shape& x, const Shape& w, const ConvParams& params);
// Throws Error naming `op` and `what` unless `actual` equals `expected`.
void requireShape(const char* op, const char* what, const Shape& actual, const Shape& expected);
// The tensor seen as [N, C, D, H, W] (a 4D tensor gets depth 1).
Tensor as5d(const Tensor& tensor);

// One phase of a transposed convolution along one axis: the outputs i = phase + stride*j, j < count,
// are sums over t < taps of weight tap firstTap - stride*t times gradient element j + offset + t
// (offset relative to the unpadded gradient; it may be negative).
struct Phase {
  int64_t phase = 0;
  int64_t count = 0;
  int64_t taps = 0;
  int64_t firstTap = 0;
  int64_t offset = 0;
};

// The `stride` phases of the transposed convolution that maps an axis of `outputSize` back to one of
// `inputSize` (kernel size `kernel`, padding `padding`); phases with no outputs are left out.
std::vector<Phase> transposedPhases(int64_t inputSize, int64_t kernel, int stride, int padding);

}  // namespace smokesvd::ops::conv
