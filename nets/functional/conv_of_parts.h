// One group of output channels of a convolution of a channel concatenation, without forming either
// (autograd over the kernels of nets/ops/conv.h):
//
//   Var convOfParts(Tape& tape, const std::vector<Var>& parts, const Var& w, const Var& bias,
//                   const ops::ConvParams& params, int64_t outBegin, int64_t outEnd);
//     y = conv(cat(parts, 1), w[outBegin:outEnd]) + bias[outBegin:outEnd]
//       = sum_i conv(parts_i, w[outBegin:outEnd, o_i : o_i + C_i]) + bias[outBegin:outEnd]
//     parts N,C_i,H,W or N,C_i,D,H,W agreeing on every other axis; o_i = C_0 + ... + C_{i-1};
//     w [K, sum C_i, k...]; bias [K] or nullptr; 0 <= outBegin < outEnd <= K.
//   Gradients: d parts_i = convBackwardInput(dy, w block i); d w = convBackwardWeight(parts_i, dy) at the
//   block's place, zeros elsewhere; d bias = dy summed, at [outBegin, outEnd), zeros elsewhere.
//
// For maps whose channels do not fit one tensor (DeviceInfo::maxTensorBytes): UNet3+'s decoder keeps
// such a map as channel parts (nets/models/unet3plus.h). The products are those of conv(cat(parts));
// they are summed part by part, so the result differs from it by rounding only.
//
// Registered for `smokesvd op` as "conv_of_parts" (parts a, b, optional c; w; optional bias; attributes
// stride, padding, out_begin, out_end).
#pragma once

#include <vector>

#include "nets/autograd/tape.h"
#include "nets/ops/conv.h"

namespace smokesvd::fn {

Var convOfParts(Tape& tape, const std::vector<Var>& parts, const Var& w, const Var& bias, const ops::ConvParams& params,
                int64_t outBegin, int64_t outEnd);

}  // namespace smokesvd::fn
