// Concatenation and slicing along the channel axis (axis 1) of N,C,... tensors (N,C,H,W or N,C,D,H,W;
// any rank >= 2): torch.cat(inputs, dim=1) and x[:, begin:end].
#pragma once

#include <span>

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// The shape of the concatenation of tensors that agree on every axis but 1; Error otherwise.
Shape concatShape(std::span<const Shape> shapes);

// y = cat(inputs, axis 1)
void concatChannels(Stream& stream, std::span<const Tensor> inputs, const Tensor& y);
// y = x[:, begin:end]
void sliceChannels(Stream& stream, const Tensor& x, int64_t begin, int64_t end, const Tensor& y);
// destination[:, to : to + count] = source[:, from : from + count]; other channels of destination untouched.
void copyChannels(Stream& stream, const Tensor& source, int64_t from, const Tensor& destination, int64_t to,
                  int64_t count);

}  // namespace smokesvd::ops
