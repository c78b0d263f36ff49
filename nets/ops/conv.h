// Convolution kernels on float32 NCHW / NCDHW tensors (batch >= 1), in PyTorch's conventions:
//   conv weight [Cout, Cin, kD, kH, kW] (2D: [Cout, Cin, kH, kW]), bias [Cout];
//   transposed-conv weight [Cin, Cout, kD, kH, kW];
//   conv output size floor((in + 2p - k) / s) + 1, transposed (in - 1) s - 2p + k + outputPadding.
// A 2D tensor is run as 3D with depth 1 (one code path). Each function records its dispatches into
// the stream and writes a caller-provided output of the exact expected shape (Error otherwise).
// See docs/convolution.md for the kernels and their blocking.
#pragma once

#include <array>
#include <cstdint>

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

// Stride and zero padding, the same along every spatial axis.
struct ConvParams {
  int stride = 1;
  int padding = 0;
  int outputPadding = 0;  // transposed convolution only: extra output rows at the high end, < stride
  // Convolution only: it reads its input through leaky ReLU with this negative slope (0: ReLU),
  // y = conv(f(x), w) + b with f(v) = v > 0 ? v : inputSlope v, fused into the kernels that read x;
  // 1 reads x as it is. Its input gradient is convBackwardActivatedInput's.
  float inputSlope = 1.0f;
};

// In what order the direct pass fetches an input channel's rows and taps (docs/convolution.md,
// conv_direct): each kernel row's just before its multiply-adds, or all of the channel's first.
enum class DirectFetch { DeviceDefault, PerKernelRow, PerInputChannel };

// Register blocking of the kernels; 0 (and DeviceDefault) lets the host choose from the shapes and the
// device. Every choice gives the same result up to float rounding order; it only changes speed.
struct ConvBlocking {
  int pixels = 0;        // consecutive outputs along x per invocation, 1..16
  int channelVec4s = 0;  // output channels per invocation, in groups of 4, 1..4
  DirectFetch fetch = DirectFetch::DeviceDefault;  // the direct pass (forward, backward-input, transposed)
};

// The GroupNorm-then-SiLU a convolution can read its input through (convForwardOfNormSilu): each value v
// of x [N, C, ...] is read as SiLU((v - mean) rstd gamma[c] + beta[c]), (mean, rstd) of its sample's group
// from `stats` ([N * groups, 2], ops::groupNormStats), gamma and beta [C]; the zero padding stays zero.
// It is fn::groupNormSilu's output without the tensor: the same values, made where the convolution copies
// its input into padded form.
struct NormSiluInput {
  const Tensor* stats = nullptr;
  const Tensor* gamma = nullptr;
  const Tensor* beta = nullptr;
  int64_t groups = 1;
};

// A convolution's input as its forward pass copied it into zero-padded form, through the activation the
// convolution reads it with, kept so that the weight gradient reads it instead of making the copy again
// (convForward's `keep`, convBackwardWeight's `padded`). Its tensor is undefined where the forward made no
// copy (a pointwise convolution). A kept copy too small for the weight gradient's blocking (on a device
// whose direct pass runs shorter rows) is not used; the weight gradient then pads x itself.
struct PaddedInput {
  Tensor tensor;                  // [N, C, size], flat, with four floats of slack
  std::array<int64_t, 3> size{};  // along z, y, x
};

Shape convOutputShape(const Shape& x, const Shape& w, const ConvParams& params);
Shape convTransposeOutputShape(const Shape& x, const Shape& w, const ConvParams& params);

// y = conv(f(x), w) + b, f the leaky ReLU of params.inputSlope (none at 1); given `keep`, the padded f(x) is
// left there for convBackwardWeight.
void convForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const ConvParams& params,
                 const Tensor& y, ConvBlocking blocking = {}, PaddedInput* keep = nullptr);
// y = addend + conv(f(x), w) + b: convForward with a tensor of y's shape added as y is written (a residual
// connection, without a pass of its own). Its gradients are convForward's, and dy itself for the addend.
void convForwardPlus(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& addend,
                     const ConvParams& params, const Tensor& y, ConvBlocking blocking = {},
                     PaddedInput* keep = nullptr);
// dx = d<dy, conv(x, w)>/dx: a transposed convolution of dy (dx's shape says the input size); params.inputSlope
// must be 1 (see convBackwardActivatedInput).
void convBackwardInput(Stream& stream, const Tensor& dy, const Tensor& w, const ConvParams& params,
                       const Tensor& dx, ConvBlocking blocking = {});
// dx = addend + d<dy, conv(f(x), w)>/dx = addend + f'(x) * (the transposed convolution of dy), f the leaky ReLU
// of params.inputSlope: the input gradient of a convolution that reads its input through it, added to the
// gradient so far (`addend`, of x's shape; nullptr: 0) as it is written.
void convBackwardActivatedInput(Stream& stream, const Tensor& dy, const Tensor& w, const Tensor& x,
                                const ConvParams& params, const Tensor& dx, const Tensor* addend = nullptr,
                                ConvBlocking blocking = {});
// dw = d<dy, conv(f(x), w)>/dw (f as in convForward), reading `padded` (the forward's kept copy of f(x)) where
// given and large enough.
void convBackwardWeight(Stream& stream, const Tensor& x, const Tensor& dy, const ConvParams& params,
                        const Tensor& dw, ConvBlocking blocking = {}, const PaddedInput* padded = nullptr);
// db[k] = sum of dy over the batch and every position of channel k (conv and transposed conv alike).
void convBackwardBias(Stream& stream, const Tensor& dy, const Tensor& db);

// y = (addend +) conv(f(x), w) + b, f the GroupNorm-then-SiLU of `norm`; not a pointwise convolution that
// runs unpadded (a 1x1 kernel on positions of a multiple of 4), params.inputSlope 1. Its input gradient is convBackwardInput's (the
// gradient at f(x)) through groupNormBackward with NormActivation::Silu.
void convForwardOfNormSilu(Stream& stream, const Tensor& x, const NormSiluInput& norm, const Tensor& w,
                           const Tensor* bias, const Tensor* addend, const ConvParams& params, const Tensor& y,
                           ConvBlocking blocking = {}, PaddedInput* keep = nullptr);
// dw = d<dy, conv(f(x), w)>/dw, f as in convForwardOfNormSilu (the forward's kept copy `padded` read where given
// and large enough).
void convBackwardWeightOfNormSilu(Stream& stream, const Tensor& x, const NormSiluInput& norm, const Tensor& dy,
                                  const ConvParams& params, const Tensor& dw, ConvBlocking blocking = {},
                                  const PaddedInput* padded = nullptr);

// y = convTranspose(x, w) + b, the adjoint of conv with the same weight (weight [Cin, Cout, k...]).
void convTransposeForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias,
                          const ConvParams& params, const Tensor& y, ConvBlocking blocking = {});
// dx = conv(dy, w), the forward convolution.
void convTransposeBackwardInput(Stream& stream, const Tensor& dy, const Tensor& w, const ConvParams& params,
                                const Tensor& dx, ConvBlocking blocking = {});
// dw: the conv weight gradient with the roles of input and output gradient exchanged.
void convTransposeBackwardWeight(Stream& stream, const Tensor& x, const Tensor& dy, const ConvParams& params,
                                 const Tensor& dw, ConvBlocking blocking = {});

}  // namespace smokesvd::ops
