// The convolution kernels one by one (shaders/nn/conv_*.comp): each function records one dispatch,
// or two for a two-stage reduction. nets/ops/conv.cpp composes them into the public operations.
#pragma once

#include "nets/ops/conv_geometry.h"
#include "runtime/device_info.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops::conv {

// Block sizes actually used: the request with every 0 replaced by the default for the shape and the
// device class (CPU or GPU). Throws Error for a request out of range.
ConvBlocking directBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t gridWidth, int64_t kernelDepth,
                             int64_t outChannels);
ConvBlocking weightGradBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t outWidth,
                                int64_t outChannels);
int64_t roundUp(int64_t value, int64_t multiple);

// A zero-padded copy [N, C, size] of an [N, C, D, H, W] tensor placed at `low`; size[2] is rounded up to
// a multiple of 4. Rows and columns of the source past `size` are left out. The tensor is flat, with four
// floats of slack after the padded data.
struct Padded {
  Tensor tensor;
  int64_t batch = 0;
  int64_t channels = 0;
  Int3 size{};
};
// What the padding copy applies to each value of x it copies (the padding itself stays zero): leaky ReLU
// with the negative slope inputSlope (1: nothing; ConvParams::inputSlope), or, given `norm`, GroupNorm then
// SiLU (ops::NormSiluInput).
struct PadActivation {
  float inputSlope = 1.0f;
  const NormSiluInput* norm = nullptr;
};
Padded pad(Stream& stream, const Tensor& x5, const Int3& low, const Int3& size, const PadActivation& activation = {});
// The extent pad() gives a padded copy of extent `size`: the row rounded up to a multiple of 4.
Int3 paddedExtent(const Int3& size);

// Where packed weight [c, r, s, t, k] comes from in a weight tensor: k and c are source axes with element
// strides strideK and strideC; the tap (r, s, t) reads source tap firstTap + (r, s, t) * tapStep of a
// source kernel of extent sourceKernel.
struct WeightPacking {
  int64_t outChannels = 0;  // K of the packed layout
  int64_t inChannels = 0;   // C of the packed layout
  int64_t strideK = 0;
  int64_t strideC = 0;
  Int3 sourceKernel{};
  Int3 taps{};
  Int3 firstTap{};
  Int3 tapStep{1, 1, 1};
};
// Packed weights [C, taps, paddedK] (zero for k >= K), at least one vec4.
Tensor packWeights(Stream& stream, const Tensor& w, const WeightPacking& packing, int64_t paddedK);

// One dispatch of the direct convolution (shaders/nn/conv_direct.comp) into y [N, K, outSize].
struct DirectPass {
  Int3 taps{};             // all 0 for a phase that gathers no taps (it writes the bias only)
  int stride = 1;
  Int3 grid{};             // grid positions along z, y, x
  Int3 inStart{};          // padded-input position read by grid position 0, tap 0
  Int3 outStep{1, 1, 1};   // output positions between neighbouring grid positions
  Int3 outStart{};         // output position of grid position 0
};
// What the direct and pointwise passes do to each output value v as they write it: y = addend + g v, with
// g = gate > 0 ? 1 : gateSlope, the derivative of leaky ReLU at `gate` (the input gradient of a convolution
// through it, ConvParams::inputSlope), and `addend` a residual connection; both of y's shape (direct: of y5's
// shape once viewed as 5-D), absent: none.
struct OutputTerms {
  const Tensor* gate = nullptr;
  float gateSlope = 1.0f;
  const Tensor* addend = nullptr;
};
void direct(Stream& stream, const Padded& xp, const Tensor& packedWeights, const Tensor* bias, const Tensor& y5,
            const DirectPass& pass, const ConvBlocking& blocking, const OutputTerms& terms = {});

// Output gradient [N, K, D, H, W] as rows with channels last: [N*D*H, paddedWidth, paddedK], zero-filled.
Tensor packGrad(Stream& stream, const Tensor& g5, int64_t paddedWidth, int64_t paddedK);

// dw [K, C, k...] from the padded forward input and the packed output gradient (two-stage reduction).
void weightGrad(Stream& stream, const ConvGeometry& g, const Padded& xp, const Tensor& gradRows, const Tensor& dw,
                int pixels, int channelVec4s);

// Pointwise convolutions (1^d kernel, stride 1, no padding, positions D*H*W a multiple of 4) run on the
// unpadded tensors (shaders/nn/conv_pointwise*.comp).
bool isPointwise(const ConvGeometry& g);
// Positions and output channels per invocation of the pointwise pass: ConvBlocking{positions, channels}.
// `requested` is read as pixels -> positions (rounded up to vec4s), channelVec4s -> 4 * channels.
struct PointwiseBlocking {
  int positionVec4s = 0;
  int channels = 0;    // a multiple of 4, or every output channel in one block
  int inputGroup = 1;  // input channels fetched before their multiply-adds (the device's default)
};
PointwiseBlocking pointwiseBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t outChannels);
// y [N, K, P] = bias + wp^T x for x [N, C, P]; wp [C, rowK]: packed by packWeights with rowK =
// pointwisePaddedK(blocking, K), or any [C, K] tensor with K a multiple of 4 (rowK = K) read in place.
int64_t pointwisePaddedK(const PointwiseBlocking& blocking, int64_t outChannels);
// inputSlope != 1 reads x through leaky ReLU with that negative slope (ConvParams::inputSlope).
void pointwise(Stream& stream, const Tensor& x, const Tensor& weights, int64_t rowK, const Tensor* bias,
               const Tensor& y, const PointwiseBlocking& blocking, float inputSlope = 1.0f,
               const OutputTerms& terms = {});
// dw [K, C] (any shape of K*C elements) = sum over n, p of g[n, k, p] f(x[n, c, p]), f leaky ReLU with
// inputSlope (1: f(v) = v), for x [N, C, P], g [N, K, P].
void pointwiseWeightGrad(Stream& stream, const Tensor& x, const Tensor& g, const Tensor& dw, float inputSlope = 1.0f);

// db [K] = sum of g [N, K, P] over n and p: one pass, a workgroup per channel, where a lane's share fits
// the loop budget on a CPU device; chunks of the plane and a second pass adding them otherwise.
void biasGrad(Stream& stream, const Tensor& g, const Tensor& db);

}  // namespace smokesvd::ops::conv
