#include "nets/ops/conv.h"

#include <algorithm>
#include <string>

#include "nets/ops/conv_geometry.h"
#include "nets/ops/conv_kernels.h"
#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::ops {
namespace {

using conv::ConvGeometry;
using conv::Int3;

void requireBias(const char* op, const Tensor* bias, int64_t channels) {
  if (bias != nullptr) conv::requireShape(op, "bias", bias->shape(), {channels});
}

// Output padding is only meaningful for the transposed convolution, below the stride.
void requireOutputPadding(const char* op, const ConvParams& params) {
  if (params.outputPadding < 0 || params.outputPadding >= std::max(params.stride, 1))
    throw Error(std::string(op) + ": output padding " + std::to_string(params.outputPadding) +
                " must be >= 0 and smaller than the stride " + std::to_string(params.stride));
}

int64_t taps(const Int3& kernel) { return kernel[0] * kernel[1] * kernel[2]; }

// A convolution reading its input through GroupNorm then SiLU: a padded (non-pointwise) kernel, no leaky ReLU,
// and the norm's tensors of the input's shape.
void requireNormSilu(const char* op, const ConvGeometry& g, const NormSiluInput& norm, const ConvParams& params) {
  if (norm.stats == nullptr || norm.gamma == nullptr || norm.beta == nullptr)
    throw Error(std::string(op) + ": the norm needs its statistics, gamma and beta");
  if (conv::isPointwise(g))
    throw Error(std::string(op) + ": a pointwise kernel reads its input unpadded; normalise it with fn::groupNormSilu");
  if (params.inputSlope != 1.0f)
    throw Error(std::string(op) + ": input slope " + std::to_string(params.inputSlope) + ", expected 1");
  if (norm.groups < 1 || g.inChannels % norm.groups != 0)
    throw Error(std::string(op) + ": " + std::to_string(norm.groups) + " groups do not divide " +
                std::to_string(g.inChannels) + " channels");
  conv::requireShape(op, "norm statistics", norm.stats->shape(), {g.batch * norm.groups, 2});
  conv::requireShape(op, "norm gamma", norm.gamma->shape(), {g.inChannels});
  conv::requireShape(op, "norm beta", norm.beta->shape(), {g.inChannels});
}

// The input activation belongs to the convolution's own forward, weight-gradient and activated-input passes.
void requireNoInputActivation(const char* op, const ConvParams& params) {
  if (params.inputSlope != 1.0f)
    throw Error(std::string(op) + ": input slope " + std::to_string(params.inputSlope) +
                ", expected 1 (a leaky ReLU on the input belongs to conv forward, conv backward weight and "
                "convBackwardActivatedInput)");
}

// y = wp^T x + b (pointwise) or dx = w^T dy (its backward input, `transposedWeights`): pack w as [C, K],
// one pointwise pass over the unpadded tensors. The backward input reads w [K, C] in place where C is a
// multiple of 4, and packs it otherwise.
void pointwise(Stream& stream, const ConvGeometry& g, const Tensor& x, const Tensor& w, const Tensor* bias,
               const Tensor& y, ConvBlocking blocking, bool transposedWeights, float inputSlope = 1.0f,
               const conv::OutputTerms& terms = {}) {
  const int64_t in = transposedWeights ? g.outChannels : g.inChannels;
  const int64_t out = transposedWeights ? g.inChannels : g.outChannels;
  const conv::PointwiseBlocking chosen = conv::pointwiseBlocking(stream.context().info(), blocking, out);
  if (transposedWeights && out % 4 == 0)
    return conv::pointwise(stream, x, w, out, bias, y, chosen, inputSlope, terms);
  conv::WeightPacking packing;
  packing.outChannels = out;
  packing.inChannels = in;
  packing.strideK = transposedWeights ? 1 : g.inChannels;
  packing.strideC = transposedWeights ? g.inChannels : 1;
  packing.sourceKernel = {1, 1, 1};
  packing.taps = {1, 1, 1};
  const int64_t rowK = conv::pointwisePaddedK(chosen, out);
  conv::pointwise(stream, x, conv::packWeights(stream, w, packing, rowK), rowK, bias, y, chosen, inputSlope, terms);
}

// y = addend + conv(f(x), w) + b (no addend: 0): pad f(x), pack w as [C, k..., K], one direct pass with
// the conv's stride.
void forward(Stream& stream, const ConvGeometry& g, const Tensor& x, const Tensor& w, const Tensor* bias,
             const Tensor& y, ConvBlocking blocking, const conv::PadActivation& activation,
             const Tensor* addend = nullptr, PaddedInput* keep = nullptr) {
  if (conv::isPointwise(g))
    return pointwise(stream, g, x, w, bias, y, blocking, false, activation.inputSlope, {.addend = addend});
  const ConvBlocking chosen =
      conv::directBlocking(stream.context().info(), blocking, g.output[2], g.kernel[0], g.outChannels);
  const int pixels = chosen.pixels, channelVec4s = chosen.channelVec4s;
  const int64_t xBlocks = (g.output[2] + pixels - 1) / pixels;
  const Int3 size{(g.output[0] - 1) * g.stride + g.kernel[0], (g.output[1] - 1) * g.stride + g.kernel[1],
                  (xBlocks * pixels - 1) * g.stride + g.kernel[2]};
  const conv::Padded xp = conv::pad(stream, conv::as5d(x), g.padding, size, activation);
  if (keep != nullptr) *keep = {xp.tensor, xp.size};

  conv::WeightPacking packing;
  packing.outChannels = g.outChannels;
  packing.inChannels = g.inChannels;
  packing.strideK = g.inChannels * taps(g.kernel);
  packing.strideC = taps(g.kernel);
  packing.sourceKernel = g.kernel;
  packing.taps = g.kernel;
  const Tensor packed =
      conv::packWeights(stream, w, packing, conv::roundUp(g.outChannels, 4 * static_cast<int64_t>(channelVec4s)));

  conv::DirectPass pass;
  pass.taps = g.kernel;
  pass.stride = g.stride;
  pass.grid = g.output;
  conv::direct(stream, xp, packed, bias, conv::as5d(y), pass, chosen, {.addend = addend});
}

// dx = d<dy, conv(x, w)>/dx (+ b): the transposed convolution, as stride^3 phases, with the output terms
// (conv::OutputTerms: a gate, an addend) applied as each output is written. Phase (rz, ry, rx)
// writes the outputs i = r + stride*j; each is a stride-1 direct convolution of the padded dy with a
// flipped, sub-sampled, channel-transposed copy of w.
void transposed(Stream& stream, const ConvGeometry& g, const Tensor& dy, const Tensor& w, const Tensor* bias,
                const Tensor& dx, ConvBlocking blocking, const conv::OutputTerms& terms = {}) {
  if (conv::isPointwise(g))
    return pointwise(stream, g, dy, w, bias, dx, blocking, true, 1.0f, terms);
  std::array<std::vector<conv::Phase>, 3> phases;
  Int3 low{}, size{};
  int64_t widest = 1;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    phases[axis] = conv::transposedPhases(g.input[axis], g.kernel[axis], g.stride, static_cast<int>(g.padding[axis]));
    for (const conv::Phase& p : phases[axis])
      if (p.taps > 0) low[axis] = std::max(low[axis], -p.offset);
    if (axis == 2)
      for (const conv::Phase& p : phases[axis]) widest = std::max(widest, p.count);
  }
  const ConvBlocking chosen =
      conv::directBlocking(stream.context().info(), blocking, widest, g.kernel[0], g.inChannels);
  const int pixels = chosen.pixels, channelVec4s = chosen.channelVec4s;
  for (std::size_t axis = 0; axis < 3; ++axis) {
    size[axis] = 1;
    for (const conv::Phase& p : phases[axis]) {
      if (p.taps == 0) continue;
      const int64_t positions = axis == 2 ? (p.count + pixels - 1) / pixels * pixels : p.count;
      size[axis] = std::max(size[axis], positions - 1 + p.taps + p.offset + low[axis]);
    }
  }
  const conv::Padded dyp = conv::pad(stream, conv::as5d(dy), low, size);
  const Tensor dx5 = conv::as5d(dx);
  const int64_t paddedK = conv::roundUp(g.inChannels, 4 * static_cast<int64_t>(channelVec4s));

  for (const conv::Phase& pz : phases[0]) {
    for (const conv::Phase& py : phases[1]) {
      for (const conv::Phase& px : phases[2]) {
        const std::array<const conv::Phase*, 3> phase{&pz, &py, &px};
        conv::WeightPacking packing;
        packing.outChannels = g.inChannels;
        packing.inChannels = g.outChannels;
        packing.strideK = taps(g.kernel);
        packing.strideC = g.inChannels * taps(g.kernel);
        packing.sourceKernel = g.kernel;
        conv::DirectPass pass;
        const bool gathers = pz.taps > 0 && py.taps > 0 && px.taps > 0;
        for (std::size_t axis = 0; axis < 3; ++axis) {
          const conv::Phase& p = *phase[axis];
          packing.taps[axis] = gathers ? p.taps : 0;
          packing.firstTap[axis] = p.firstTap;
          packing.tapStep[axis] = -g.stride;
          pass.grid[axis] = p.count;
          pass.inStart[axis] = gathers ? p.offset + low[axis] : 0;
          pass.outStep[axis] = g.stride;
          pass.outStart[axis] = p.phase;
        }
        pass.taps = packing.taps;
        if (!gathers) pass.taps = {0, 1, 1};  // no taps; keeps the kernel's row arrays non-empty
        const Tensor packed = conv::packWeights(stream, w, packing, paddedK);
        conv::direct(stream, dyp, packed, bias, dx5, pass, chosen, terms);
      }
    }
  }
}

// The forward's kept copy where it holds every value the weight gradient reads (the extent conv::pad would give
// `size`), a new padded copy of f(x) otherwise.
conv::Padded paddedForWeightGradient(Stream& stream, const ConvGeometry& g, const Tensor& x, const Int3& size,
                                     const conv::PadActivation& activation, const PaddedInput* kept) {
  const Int3 needed = conv::paddedExtent(size);
  if (kept != nullptr && kept->tensor.defined() && kept->size[0] >= needed[0] && kept->size[1] >= needed[1] &&
      kept->size[2] >= needed[2])
    return {kept->tensor, g.batch, g.inChannels, kept->size};
  return conv::pad(stream, conv::as5d(x), g.padding, size, activation);
}

void weightGradient(Stream& stream, const ConvGeometry& g, const Tensor& x, const Tensor& dy, const Tensor& dw,
                    ConvBlocking blocking, const conv::PadActivation& activation, const PaddedInput* kept) {
  if (conv::isPointwise(g)) return conv::pointwiseWeightGrad(stream, x, dy, dw, activation.inputSlope);
  const ConvBlocking chosen = conv::weightGradBlocking(stream.context().info(), blocking, g.output[2], g.outChannels);
  const int pixels = chosen.pixels, channelVec4s = chosen.channelVec4s;
  const int64_t paddedWidth = conv::roundUp(g.output[2], pixels);
  const Int3 size{(g.output[0] - 1) * g.stride + g.kernel[0], (g.output[1] - 1) * g.stride + g.kernel[1],
                  (paddedWidth - 1) * g.stride + g.kernel[2]};
  const conv::Padded xp = paddedForWeightGradient(stream, g, x, size, activation, kept);
  const Tensor rows = conv::packGrad(stream, conv::as5d(dy), paddedWidth,
                                     conv::roundUp(g.outChannels, 4 * static_cast<int64_t>(channelVec4s)));
  conv::weightGrad(stream, g, xp, rows, dw, pixels, channelVec4s);
}

}  // namespace

Shape convOutputShape(const Shape& x, const Shape& w, const ConvParams& params) {
  return conv::convGeometry("conv", x, w, params).outputShape();
}

Shape convTransposeOutputShape(const Shape& x, const Shape& w, const ConvParams& params) {
  const char* op = "conv transpose";
  requireOutputPadding(op, params);
  if ((x.size() != 4 && x.size() != 5) || w.size() != x.size())
    throw Error(std::string(op) + ": input " + toString(x) + " and weight " + toString(w) +
                " must both be 4D or both 5D");
  if (w[0] != x[1])
    throw Error(std::string(op) + ": weight " + toString(w) + " expects " + std::to_string(w[0]) +
                " input channels, input " + toString(x) + " has " + std::to_string(x[1]));
  Shape y{x[0], w[1]};
  for (std::size_t axis = 2; axis < x.size(); ++axis) {
    const int64_t size = (x[axis] - 1) * params.stride - 2 * params.padding + w[axis] + params.outputPadding;
    if (size < 1) throw Error(std::string(op) + ": input " + toString(x) + " and weight " + toString(w) +
                              " give an empty output");
    y.push_back(size);
  }
  return y;
}

void convForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const ConvParams& params,
                 const Tensor& y, ConvBlocking blocking, PaddedInput* keep) {
  const char* op = "conv forward";
  const ConvGeometry g = conv::convGeometry(op, x.shape(), w.shape(), params);
  conv::requireShape(op, "output", y.shape(), g.outputShape());
  requireBias(op, bias, g.outChannels);
  forward(stream, g, x, w, bias, y, blocking, {.inputSlope = params.inputSlope}, nullptr, keep);
}

void convForwardPlus(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias, const Tensor& addend,
                     const ConvParams& params, const Tensor& y, ConvBlocking blocking, PaddedInput* keep) {
  const char* op = "conv forward plus";
  const ConvGeometry g = conv::convGeometry(op, x.shape(), w.shape(), params);
  conv::requireShape(op, "output", y.shape(), g.outputShape());
  conv::requireShape(op, "addend", addend.shape(), g.outputShape());
  requireBias(op, bias, g.outChannels);
  forward(stream, g, x, w, bias, y, blocking, {.inputSlope = params.inputSlope}, &addend, keep);
}

void convBackwardInput(Stream& stream, const Tensor& dy, const Tensor& w, const ConvParams& params, const Tensor& dx,
                       ConvBlocking blocking) {
  const char* op = "conv backward input";
  requireNoInputActivation(op, params);
  const ConvGeometry g = conv::convGeometry(op, dx.shape(), w.shape(), params);
  conv::requireShape(op, "output gradient", dy.shape(), g.outputShape());
  transposed(stream, g, dy, w, nullptr, dx, blocking);
}

void convBackwardActivatedInput(Stream& stream, const Tensor& dy, const Tensor& w, const Tensor& x,
                                const ConvParams& params, const Tensor& dx, const Tensor* addend,
                                ConvBlocking blocking) {
  const char* op = "conv backward activated input";
  const ConvGeometry g = conv::convGeometry(op, dx.shape(), w.shape(), params);
  conv::requireShape(op, "output gradient", dy.shape(), g.outputShape());
  conv::requireShape(op, "input", x.shape(), dx.shape());
  if (addend != nullptr) conv::requireShape(op, "addend", addend->shape(), dx.shape());
  transposed(stream, g, dy, w, nullptr, dx, blocking, {.gate = &x, .gateSlope = params.inputSlope, .addend = addend});
}

void convBackwardWeight(Stream& stream, const Tensor& x, const Tensor& dy, const ConvParams& params, const Tensor& dw,
                        ConvBlocking blocking, const PaddedInput* padded) {
  const char* op = "conv backward weight";
  const ConvGeometry g = conv::convGeometry(op, x.shape(), dw.shape(), params);
  conv::requireShape(op, "output gradient", dy.shape(), g.outputShape());
  weightGradient(stream, g, x, dy, dw, blocking, {.inputSlope = params.inputSlope}, padded);
}

void convForwardOfNormSilu(Stream& stream, const Tensor& x, const NormSiluInput& norm, const Tensor& w,
                           const Tensor* bias, const Tensor* addend, const ConvParams& params, const Tensor& y,
                           ConvBlocking blocking, PaddedInput* keep) {
  const char* op = "conv forward of norm silu";
  const ConvGeometry g = conv::convGeometry(op, x.shape(), w.shape(), params);
  conv::requireShape(op, "output", y.shape(), g.outputShape());
  if (addend != nullptr) conv::requireShape(op, "addend", addend->shape(), g.outputShape());
  requireBias(op, bias, g.outChannels);
  requireNormSilu(op, g, norm, params);
  forward(stream, g, x, w, bias, y, blocking, {.norm = &norm}, addend, keep);
}

void convBackwardWeightOfNormSilu(Stream& stream, const Tensor& x, const NormSiluInput& norm, const Tensor& dy,
                                  const ConvParams& params, const Tensor& dw, ConvBlocking blocking,
                                  const PaddedInput* padded) {
  const char* op = "conv backward weight of norm silu";
  const ConvGeometry g = conv::convGeometry(op, x.shape(), dw.shape(), params);
  conv::requireShape(op, "output gradient", dy.shape(), g.outputShape());
  requireNormSilu(op, g, norm, params);
  weightGradient(stream, g, x, dy, dw, blocking, {.norm = &norm}, padded);
}

void convBackwardBias(Stream& stream, const Tensor& dy, const Tensor& db) {
  if (dy.rank() != 4 && dy.rank() != 5)
    throw Error("conv backward bias: output gradient " + toString(dy.shape()) + " must be 4D or 5D");
  conv::requireShape("conv backward bias", "bias gradient", db.shape(), {dy.size(1)});
  conv::biasGrad(stream, dy, db);
}

void convTransposeForward(Stream& stream, const Tensor& x, const Tensor& w, const Tensor* bias,
                          const ConvParams& params, const Tensor& y, ConvBlocking blocking) {
  const char* op = "conv transpose forward";
  requireNoInputActivation(op, params);
  conv::requireShape(op, "output", y.shape(), convTransposeOutputShape(x.shape(), w.shape(), params));
  const ConvGeometry g = conv::convGeometry(op, y.shape(), w.shape(), params);
  conv::requireShape(op, "input", x.shape(), g.outputShape());
  requireBias(op, bias, g.inChannels);
  transposed(stream, g, x, w, bias, y, blocking);
}

void convTransposeBackwardInput(Stream& stream, const Tensor& dy, const Tensor& w, const ConvParams& params,
                                const Tensor& dx, ConvBlocking blocking) {
  const char* op = "conv transpose backward input";
  requireOutputPadding(op, params);
  requireNoInputActivation(op, params);
  const ConvGeometry g = conv::convGeometry(op, dy.shape(), w.shape(), params);
  conv::requireShape(op, "input gradient", dx.shape(), g.outputShape());
  forward(stream, g, dy, w, nullptr, dx, blocking, {});
}

void convTransposeBackwardWeight(Stream& stream, const Tensor& x, const Tensor& dy, const ConvParams& params,
                                 const Tensor& dw, ConvBlocking blocking) {
  const char* op = "conv transpose backward weight";
  requireOutputPadding(op, params);
  requireNoInputActivation(op, params);
  const ConvGeometry g = conv::convGeometry(op, dy.shape(), dw.shape(), params);
  conv::requireShape(op, "input", x.shape(), g.outputShape());
  weightGradient(stream, g, dy, x, dw, blocking, {}, nullptr);
}

}  // namespace smokesvd::ops
