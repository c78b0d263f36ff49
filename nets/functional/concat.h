// Differentiable concatenation and slicing along channels (autograd wrappers of nets/ops/concat.h).
//
//   Var concatChannels(Tape& tape, const std::vector<Var>& inputs);
//     torch.cat(inputs, dim=1) for N,C,... tensors that agree on every other axis; gradient: the matching
//     channel slice of the upstream gradient for each input.
//   Var sliceChannels(Tape& tape, const Var& x, int64_t begin, int64_t end);
//     x[:, begin:end] (0 <= begin <= end <= C); gradient: the upstream gradient in channels [begin, end),
//     zeros elsewhere.
//   Var sliceBatch(Tape& tape, const Var& x, int64_t begin, int64_t end);
//     x[begin:end] along the first axis (e.g. views of a stack of images [V, 1, h, w]): x's items seen as the
//     channels of one item, x.reshape(1, N, -1)[:, begin:end].reshape(end - begin, ...); gradient as sliceChannels'.
//
// Registered for `smokesvd op` as "concat_channels" (inputs a, b; optional c, d, e, f),
// "slice_channels" and "slice_batch" (x; attributes begin, end).
#pragma once

#include <vector>

#include "nets/autograd/tape.h"

namespace smokesvd::fn {

Var concatChannels(Tape& tape, const std::vector<Var>& inputs);
Var sliceChannels(Tape& tape, const Var& x, int64_t begin, int64_t end);
Var sliceBatch(Tape& tape, const Var& x, int64_t begin, int64_t end);

}  // namespace smokesvd::fn
