#include "nets/ops/conv_kernels.h"

#include <algorithm>
#include <bit>
#include <optional>
#include <string>

#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::ops::conv {
namespace {

constexpr std::array<uint32_t, 3> kFlatWorkgroup{64, 1, 1};
// Layout kernels keep index divisions out of the lanes: workgroup y and z number rows and planes
// (values shared by the workgroup), lanes run along a row, and an invocation writes a run of vec4s.
constexpr std::array<uint32_t, 3> kGridWorkgroup{8, 1, 1};
constexpr std::array<uint32_t, 3> kRowWorkgroup{16, 1, 1};
constexpr uint32_t kDirectWorkgroup = 32;      // lanes along flattened output rows
constexpr uint32_t kWeightGradWorkgroup = 16;  // lanes along (input channel, kz)
// On a GPU the weight gradient splits its reduction over output rows into chunks until about this many
// invocations run, and the bias gradient splits its planes the same way.
constexpr int64_t kWeightGradInvocations = 2048;
// On a CPU device it splits them only until about this many invocations per thread of the device run: each
// chunk costs its invocations' setup and a partial sum, and two threads are busy with 128 invocations
// (docs/convolution.md, conv_weight_grad).
constexpr int64_t kCpuWeightGradInvocationsPerThread = 64;
constexpr uint32_t kPointwiseWorkgroup = 32;  // lanes along position blocks or segments
// The pointwise weight gradient splits positions into chunks of at least this many vec4s per lane until
// about kWeightGradInvocations invocations run.
constexpr int64_t kPointwiseMinChunk = 16;
// Input and output channels per invocation of the pointwise weight gradient: the fewest balanced blocks of at
// most this many on each side (12 channels: two blocks of 6). On a CPU device larger blocks cut the fetches
// per multiply-add (docs/convolution.md); on a GPU 4 (not measured there). The chunks of positions do not
// depend on the blocks (they are counted in 4 x 4 cells of the weight), so neither do the sums.
constexpr int kPointwiseGradChannelsCpu = 8, kPointwiseGradChannelsGpu = 4;
// Position vec4s a lane of the pointwise weight gradient fetches before its multiply-adds: on a CPU device
// each fetch spills the accumulators, so several steps per round trip (docs/convolution.md).
constexpr int kPointwiseGradStepsCpu = 4, kPointwiseGradStepsGpu = 1;

// Register blocks by device class, chosen from the conv-blocking sweep on each (docs/convolution.md). A
// CPU device runs a few invocations per core, so long pixel rows win for the direct pass; a GPU needs
// many invocations in flight, so shorter rows win there, while its weight gradient gains from wider
// channel blocks (fewer invocations per chunk, so the row reduction is split into more chunks).
struct DeviceDefaults {
  int directPixels2d, directPixels3d, directChannelVec4s2d, weightGradPixels, weightGradChannelVec4s;
  DirectFetch directFetch;
};
constexpr DeviceDefaults kCpuDefaults{16, 16, 2, 8, 4, DirectFetch::PerInputChannel};  // lavapipe
constexpr DeviceDefaults kGpuDefaults{4, 8, 1, 8, 4, DirectFetch::PerKernelRow};      // NVIDIA H100
// Pointwise pass: position vec4s and at most this many output channels per invocation (evenBlock: on a CPU
// 12 channels one block of 12, 48 four of 12, 64 eight of 8), and input channels fetched before their
// multiply-adds (on a CPU device each fetch spills the accumulators, docs/convolution.md).
struct PointwiseDefaults {
  int positionVec4s, channels, inputGroup;
};
constexpr PointwiseDefaults kCpuPointwise{4, 12, 2};
constexpr PointwiseDefaults kGpuPointwise{1, 8, 1};

const DeviceDefaults& defaultsFor(const DeviceInfo& device) {
  return device.type == VK_PHYSICAL_DEVICE_TYPE_CPU ? kCpuDefaults : kGpuDefaults;
}

int32_t i32(int64_t value) { return static_cast<int32_t>(value); }

// The size of the fewest balanced blocks of at most `most` that cover `count`: 12 by 8 is two blocks of 6.
int balancedBlock(int64_t count, int most) {
  const int64_t blocks = std::max<int64_t>((count + most - 1) / most, 1);
  return static_cast<int>(std::max<int64_t>((count + blocks - 1) / blocks, 1));
}

// The largest block of 2 to `most` that divides `count` evenly, else balancedBlock: a block's idle slots cost as
// much as its work (64 channels run as 8 blocks of 8 rather than 6 of 12, 48 as 4 of 12).
int evenBlock(int64_t count, int most) {
  for (int block = most; block >= 2; --block)
    if (count % block == 0) return block;
  return balancedBlock(count, most);
}

uint32_t groupsFor(int64_t items, uint32_t workgroup) {
  return static_cast<uint32_t>((items + workgroup - 1) / workgroup);
}

// out[i] = sum_j partial[j*n + i]
void sumPartials(Stream& stream, const Tensor& partial, int64_t parts, const Tensor& out) {
  const bool vec4s = out.numel() % 4 == 0;
  struct { int32_t n, parts; } push{i32(out.numel()), i32(parts)};
  stream.dispatchFlat(stream.kernel("nn/conv_sum_partials", kFlatWorkgroup, {vec4s ? 1 : 0}),
                      {partial, vec4s ? asVec4(partial) : Arg(partial), out}, push,
                      static_cast<uint64_t>(vec4s ? out.numel() / 4 : out.numel()));
}

void requireBlocking(const ConvBlocking& requested) {
  if (requested.pixels < 0 || requested.pixels > 16)
    throw Error("conv: blocking of " + std::to_string(requested.pixels) + " pixels, expected 1..16 (0: automatic)");
  if (requested.channelVec4s < 0 || requested.channelVec4s > 4)
    throw Error("conv: blocking of " + std::to_string(requested.channelVec4s) +
                " channel vec4s, expected 1..4 (0: automatic)");
}

// No more pixels per invocation than the row has (rounded up to a power of two).
int fitPixels(int pixels, int64_t width) {
  const uint64_t widest = std::bit_ceil(static_cast<uint64_t>(width));
  return static_cast<int>(std::min<uint64_t>(static_cast<uint64_t>(pixels), widest));
}

// A packing that reads the weight [K, C, taps] in its own order (the forward pass's), each row of C taps values a
// whole number of vec4s: the transpose nn/conv_pack_rows makes from vec4 fetches.
bool isPlainTranspose(const WeightPacking& p, int64_t tapCount) {
  return p.taps == p.sourceKernel && p.firstTap == Int3{0, 0, 0} && p.tapStep == Int3{1, 1, 1} &&
         p.strideC == tapCount && p.strideK == p.inChannels * tapCount && (p.inChannels * tapCount) % 4 == 0;
}

// The stride-1 backward-input packing (every tap, flipped along every axis, the channel axes exchanged) of a weight
// whose packed output channels come in whole vec4s: what nn/conv_pack_flipped makes from vec4 fetches.
bool isFlippedTranspose(const WeightPacking& p, int64_t tapCount) {
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (p.taps[axis] != p.sourceKernel[axis] || p.firstTap[axis] != p.sourceKernel[axis] - 1 || p.tapStep[axis] != -1)
      return false;
  return p.strideK == tapCount && p.strideC == p.outChannels * tapCount && p.outChannels % 4 == 0;
}

// How many invocations the weight gradient's chunks aim for on this device.
int64_t weightGradInvocations(const DeviceInfo& device) {
  if (device.type != VK_PHYSICAL_DEVICE_TYPE_CPU) return kWeightGradInvocations;
  return kCpuWeightGradInvocationsPerThread * std::max<int64_t>(device.hostThreads, 1);
}

}  // namespace

int64_t roundUp(int64_t value, int64_t multiple) { return (value + multiple - 1) / multiple * multiple; }

ConvBlocking directBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t gridWidth,
                             int64_t kernelDepth, int64_t outChannels) {
  requireBlocking(requested);
  const DeviceDefaults& d = defaultsFor(device);
  const int defaultPixels = kernelDepth > 1 ? d.directPixels3d : d.directPixels2d;
  const int pixels = requested.pixels != 0 ? requested.pixels : fitPixels(defaultPixels, gridWidth);
  // 2D kernels: the fewest balanced blocks of at most the default vec4s (3D kernels: one vec4).
  const int channelVec4s = kernelDepth > 1 ? 1 : balancedBlock((outChannels + 3) / 4, d.directChannelVec4s2d);
  return {pixels, requested.channelVec4s != 0 ? requested.channelVec4s : channelVec4s,
          requested.fetch != DirectFetch::DeviceDefault ? requested.fetch : d.directFetch};
}

ConvBlocking weightGradBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t outWidth,
                                int64_t outChannels) {
  requireBlocking(requested);
  const DeviceDefaults& d = defaultsFor(device);
  const int pixels = requested.pixels != 0 ? requested.pixels : fitPixels(d.weightGradPixels, outWidth);
  // The fewest blocks of at most the default vec4s, balanced: 12 channels one block of 3, 24 two of 3.
  const int64_t filled = (outChannels + 3) / 4;  // vec4s the output channels fill
  const int channelVec4s = balancedBlock(filled, d.weightGradChannelVec4s);
  return {pixels, requested.channelVec4s != 0 ? requested.channelVec4s : channelVec4s};
}

Int3 paddedExtent(const Int3& size) { return {size[0], size[1], roundUp(size[2], 4)}; }

Padded pad(Stream& stream, const Tensor& x5, const Int3& low, const Int3& size, const PadActivation& activation) {
  const Shape& s = x5.shape();
  Padded xp;
  xp.size = paddedExtent(size);
  xp.batch = s[0];
  xp.channels = s[1];
  // Four floats of slack: a kernel may read a whole vec4 from the last element on.
  xp.tensor = Tensor(stream.context(), {s[0] * s[1] * xp.size[0] * xp.size[1] * xp.size[2] + 4});
  const NormSiluInput* norm = activation.norm;
  struct {
    int32_t depth, height, width, paddedDepth, paddedHeight, paddedRowVec4s, lowZ, lowY, lowX;
    float slope;
    int32_t channels, channelsPerGroup;
  } push{i32(s[2]),          i32(s[3]),   i32(s[4]),   i32(xp.size[0]), i32(xp.size[1]),
         i32(xp.size[2] / 4), i32(low[0]), i32(low[1]), i32(low[2]),     activation.inputSlope,
         i32(s[1]),           norm ? i32(s[1] / norm->groups) : 1};
  const int32_t kind = norm ? 2 : activation.inputSlope != 1.0f ? 1 : 0;
  // Rows of a multiple of 4 values are read as vec4 texels.
  const bool vec4Source = s[4] % 4 == 0;
  const Arg source = vec4Source ? asVec4(x5) : Arg(x5);
  const Kernel& kernel = stream.kernel("nn/conv_pad", kRowWorkgroup, {kind, vec4Source ? 1 : 0});
  // Without a norm the source fills the norm's three (unread) bindings.
  stream.dispatch(kernel,
                  {source, xp.tensor, norm ? Arg(*norm->stats) : source, norm ? Arg(*norm->gamma) : source,
                   norm ? Arg(*norm->beta) : source},
                  push, {groupsFor(xp.size[1], kRowWorkgroup[0]), static_cast<uint32_t>(s[0] * s[1] * xp.size[0]), 1});
  return xp;
}

Tensor packWeights(Stream& stream, const Tensor& w, const WeightPacking& p, int64_t paddedK) {
  const int64_t tapCount = p.taps[0] * p.taps[1] * p.taps[2];
  const int64_t vec4s = p.inChannels * tapCount * paddedK / 4;
  struct {
    int32_t taps[4], first[4], step[4], strides[4];
  } push{{i32(p.taps[0]), i32(p.taps[1]), i32(p.taps[2]), 0},
         {i32(p.firstTap[0]), i32(p.firstTap[1]), i32(p.firstTap[2]), i32(p.outChannels)},
         {i32(p.tapStep[0]), i32(p.tapStep[1]), i32(p.tapStep[2]), i32(paddedK / 4)},
         {i32(p.strideK), i32(p.strideC), i32(p.sourceKernel[1] * p.sourceKernel[2]), i32(p.sourceKernel[2])}};
  // The same weights packed the same way earlier in the recording and not written since: that packing.
  std::string key = "conv_pack_weights";
  for (const auto& row : {push.taps, push.first, push.step, push.strides})
    for (int i = 0; i < 4; ++i) key.append(" ").append(std::to_string(row[i]));
  key.append(" ").append(std::to_string(p.inChannels));
  if (const Tensor kept = stream.derived(w, key); kept.defined()) return kept;
  // Constant weights (a frozen network) are packed once, by a stream of their own, and the packing is kept
  // with them for every later recording: a recording re-submitted (a DDIM step, a training step through a
  // frozen network) does not pack them again.
  Tensor packed = w.constant() ? w.constantDerived(key) : Tensor();
  if (!packed.defined()) {
    packed = Tensor(stream.context(), {std::max<int64_t>(vec4s, 1) * 4});
    std::optional<Stream> once;
    if (w.constant()) once.emplace(stream.context());
    Stream& into = once ? *once : stream;
    if (vec4s > 0 && isPlainTranspose(p, tapCount)) {
      struct { int32_t rowVec4s, rows, paddedRow; } rowsPush{i32(p.inChannels * tapCount / 4), i32(p.outChannels),
                                                              i32(paddedK / 4)};
      into.dispatch(into.kernel("nn/conv_pack_rows", kFlatWorkgroup), {asVec4(w), packed}, rowsPush,
                    {groupsFor(p.inChannels * tapCount / 4, kFlatWorkgroup[0]), static_cast<uint32_t>(paddedK / 4), 1});
    } else if (vec4s > 0 && isFlippedTranspose(p, tapCount)) {
      struct { int32_t channels, paddedRow; } flippedPush{i32(p.outChannels), i32(paddedK / 4)};
      into.dispatch(into.kernel("nn/conv_pack_flipped", kGridWorkgroup, {i32(tapCount)}), {asVec4(w), packed},
                    flippedPush, {groupsFor(paddedK / 4, kGridWorkgroup[0]), static_cast<uint32_t>(p.inChannels), 1});
    } else if (vec4s > 0) {
      into.dispatch(into.kernel("nn/conv_pack_weights", kGridWorkgroup), {w, packed}, push,
                    {groupsFor(paddedK / 4, kGridWorkgroup[0]), static_cast<uint32_t>(p.inChannels), 1});
    }
    if (once) {
      once->submit();
      w.keepConstantDerived(key, packed);
    }
  }
  stream.keepDerived(w, key, packed);
  return packed;
}

void direct(Stream& stream, const Padded& xp, const Tensor& packedWeights, const Tensor* bias, const Tensor& y5,
            const DirectPass& pass, const ConvBlocking& blocking, const OutputTerms& terms) {
  const int pixels = blocking.pixels, channelVec4s = blocking.channelVec4s;
  const Shape& out = y5.shape();
  const bool gates = terms.gate != nullptr && terms.gateSlope != 1.0f;
  for (const auto& [what, tensor] : {std::pair{"gate", terms.gate}, std::pair{"addend", terms.addend}})
    if (tensor != nullptr) requireShape("direct convolution", what, as5d(*tensor).shape(), out);
  const int64_t xBlocks = (pass.grid[2] + pixels - 1) / pixels;
  const int64_t items = xBlocks * pass.grid[1] * pass.grid[0];
  const int64_t channelBlock = 4 * channelVec4s;
  const int64_t kBlocks = (out[1] + channelBlock - 1) / channelBlock;
  const int64_t inSlice = xp.size[1] * xp.size[2];
  const int64_t outSlice = out[3] * out[4];
  // Every row an invocation reads starts on a vec4 when the first does and blocks advance by whole vec4s.
  const bool alignedRows = pass.inStart[2] % 4 == 0 && (pixels * pass.stride) % 4 == 0;
  struct {
    int32_t channels, inPlane, inSlice, inRow, inBase, gridD, gridH, gridW, xBlocks, outChannels, weightRow, outPlane,
        outStepZ, outStepY, outStepX, outBase;
    float gateSlope;
  } push{i32(xp.channels),
         i32(xp.size[0] * inSlice),
         i32(inSlice),
         i32(xp.size[2]),
         i32(pass.inStart[0] * inSlice + pass.inStart[1] * xp.size[2] + pass.inStart[2]),
         i32(pass.grid[0]),
         i32(pass.grid[1]),
         i32(pass.grid[2]),
         i32(xBlocks),
         i32(out[1]),
         i32(kBlocks * channelVec4s),
         i32(out[2] * outSlice),
         i32(pass.outStep[0] * outSlice),
         i32(pass.outStep[1] * out[4]),
         i32(pass.outStep[2]),
         i32(pass.outStart[0] * outSlice + pass.outStart[1] * out[4] + pass.outStart[2]),
         terms.gateSlope};
  const Kernel& kernel =
      stream.kernel("nn/conv_direct", {kDirectWorkgroup, 1, 1},
                    {i32(pass.taps[0]), i32(pass.taps[1]), i32(pass.taps[2]), pass.stride, pixels, channelVec4s,
                     bias != nullptr ? 1 : 0, alignedRows ? 1 : 0, gates ? 1 : 0, terms.addend != nullptr ? 1 : 0,
                     blocking.fetch == DirectFetch::PerInputChannel ? 1 : 0});
  const Arg biasArg = bias != nullptr ? asVec4(*bias) : asVec4(packedWeights);
  const Arg gateArg = gates ? Arg(*terms.gate) : Arg(xp.tensor);
  const Arg addendArg = terms.addend != nullptr ? Arg(*terms.addend) : Arg(xp.tensor);
  stream.dispatch(kernel, {xp.tensor, asVec4(xp.tensor), asVec4(packedWeights), biasArg, gateArg, addendArg, y5}, push,
                  {static_cast<uint32_t>(kBlocks), groupsFor(items, kDirectWorkgroup), static_cast<uint32_t>(out[0])});
}

Tensor packGrad(Stream& stream, const Tensor& g5, int64_t paddedWidth, int64_t paddedK) {
  const Shape& s = g5.shape();
  const int64_t rows = s[0] * s[2] * s[3];
  Tensor packed(stream.context(), {rows * paddedWidth * paddedK});
  struct {
    int32_t channels, rowsPerItem, width, paddedWidth, channelVec4s;
  } push{i32(s[1]), i32(s[2] * s[3]), i32(s[4]), i32(paddedWidth), i32(paddedK / 4)};
  stream.dispatch(stream.kernel("nn/conv_pack_grad", kRowWorkgroup), {g5, packed}, push,
                  {groupsFor(paddedWidth, kRowWorkgroup[0]), static_cast<uint32_t>(rows), 1});
  return packed;
}

void weightGrad(Stream& stream, const ConvGeometry& g, const Padded& xp, const Tensor& gradRows, const Tensor& dw,
                int pixels, int channelVec4s) {
  const int64_t channelBlock = 4 * channelVec4s;
  const int64_t kBlocks = (g.outChannels + channelBlock - 1) / channelBlock;
  const int64_t xBlocks = (g.output[2] + pixels - 1) / pixels;
  const int64_t rows = g.batch * g.output[0] * g.output[1];
  const int64_t lanes = g.inChannels * g.kernel[0];
  const int64_t baseInvocations = roundUp(lanes, kWeightGradWorkgroup) * kBlocks;
  const int64_t invocations = weightGradInvocations(stream.context().info());
  // At least enough chunks that no invocation loops over more than the loop budget of positions.
  const int64_t budgetChunks = (rows * xBlocks + static_cast<int64_t>(kLoopIterationBudget) - 1) /
                               static_cast<int64_t>(kLoopIterationBudget);
  const int64_t wantedChunks =
      std::clamp<int64_t>(std::max(invocations / baseInvocations, budgetChunks), 1, rows);
  const int64_t rowsPerChunk = (rows + wantedChunks - 1) / wantedChunks;
  const int64_t chunks = (rows + rowsPerChunk - 1) / rowsPerChunk;
  const Tensor partial = chunks == 1 ? dw : Tensor(stream.context(), {chunks * dw.numel()});

  const int64_t inSlice = xp.size[1] * xp.size[2];
  struct {
    int32_t channels, inPlane, inSlice, inRow, outHeight, rowsPerItem, rows, rowsPerChunk, xBlocks, gradRow,
        outChannels;
  } push{i32(g.inChannels), i32(xp.size[0] * inSlice), i32(inSlice), i32(xp.size[2]),
         i32(g.output[1]),  i32(g.output[0] * g.output[1]), i32(rows), i32(rowsPerChunk),
         i32(xBlocks),      i32(kBlocks * channelVec4s), i32(g.outChannels)};
  const Kernel& kernel = stream.kernel(
      "nn/conv_weight_grad", {kWeightGradWorkgroup, 1, 1},
      {i32(g.kernel[0]), i32(g.kernel[1]), i32(g.kernel[2]), g.stride, pixels, channelVec4s,
       (pixels * g.stride) % 4 == 0 ? 1 : 0});
  stream.dispatch(kernel, {xp.tensor, asVec4(xp.tensor), asVec4(gradRows), partial}, push,
                  {groupsFor(lanes, kWeightGradWorkgroup), static_cast<uint32_t>(kBlocks),
                   static_cast<uint32_t>(chunks)});
  if (chunks > 1) sumPartials(stream, partial, chunks, dw);
}

bool isPointwise(const ConvGeometry& g) {
  const int64_t positions = g.input[0] * g.input[1] * g.input[2];
  return g.kernel == Int3{1, 1, 1} && g.output == g.input && g.padding == Int3{0, 0, 0} && positions % 4 == 0;
}

PointwiseBlocking pointwiseBlocking(const DeviceInfo& device, ConvBlocking requested, int64_t outChannels) {
  requireBlocking(requested);
  const PointwiseDefaults& d = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU ? kCpuPointwise : kGpuPointwise;
  const int positionVec4s = requested.pixels != 0 ? (requested.pixels + 3) / 4 : d.positionVec4s;
  const int64_t filled = (outChannels + 3) / 4;  // vec4s the output channels fill
  const int channelVec4s = requested.channelVec4s != 0 ? requested.channelVec4s : evenBlock(filled, d.channels / 4);
  const int channels = 4 * channelVec4s;
  return {positionVec4s, outChannels <= channels ? static_cast<int>(outChannels) : channels, d.inputGroup};
}

int64_t pointwisePaddedK(const PointwiseBlocking& blocking, int64_t outChannels) {
  return roundUp(outChannels, roundUp(blocking.channels, 4));
}

void pointwise(Stream& stream, const Tensor& x, const Tensor& weights, int64_t rowK, const Tensor* bias,
               const Tensor& y, const PointwiseBlocking& blocking, float inputSlope, const OutputTerms& terms) {
  if (rowK % 4 != 0 || rowK < y.size(1) || weights.numel() < x.size(1) * rowK)
    throw Error("pointwise convolution: weights of " + std::to_string(weights.numel()) + " elements in rows of " +
                std::to_string(rowK) + ", expected rows of a multiple of 4 of at least " + std::to_string(y.size(1)) +
                " for " + std::to_string(x.size(1)) + " input channels");
  const int64_t planeVec4s = y.numel() / (y.size(0) * y.size(1)) / 4;
  const int64_t kBlocks = (y.size(1) + blocking.channels - 1) / blocking.channels;
  const int64_t items = (planeVec4s + blocking.positionVec4s - 1) / blocking.positionVec4s;
  for (const auto& [what, tensor] : {std::pair{"gate", terms.gate}, std::pair{"addend", terms.addend}})
    if (tensor != nullptr) requireShape("pointwise convolution", what, tensor->shape(), y.shape());
  struct {
    int32_t channels, planeVec4s, outChannels, weightRow;
    float inputSlope, gateSlope;
  } push{i32(x.size(1)), i32(planeVec4s), i32(y.size(1)), i32(rowK / 4), inputSlope, terms.gateSlope};
  const bool gates = terms.gate != nullptr && terms.gateSlope != 1.0f;
  const Kernel& kernel = stream.kernel("nn/conv_pointwise", {kPointwiseWorkgroup, 1, 1},
                                       {blocking.positionVec4s, blocking.channels, bias != nullptr ? 1 : 0,
                                        inputSlope != 1.0f ? 1 : 0, gates ? 1 : 0, terms.addend != nullptr ? 1 : 0,
                                        blocking.inputGroup});
  const Arg biasArg = bias != nullptr ? asVec4(*bias) : asVec4(weights);
  const Arg gateArg = gates ? asVec4(*terms.gate) : asVec4(weights);
  const Arg addendArg = terms.addend != nullptr ? asVec4(*terms.addend) : asVec4(weights);
  stream.dispatch(kernel, {asVec4(x), asVec4(weights), biasArg, gateArg, addendArg, y}, push,
                  {static_cast<uint32_t>(kBlocks), groupsFor(items, kPointwiseWorkgroup),
                   static_cast<uint32_t>(y.size(0))});
}

void pointwiseWeightGrad(Stream& stream, const Tensor& x, const Tensor& g, const Tensor& dw, float inputSlope) {
  const DeviceInfo& device = stream.context().info();
  const int64_t batch = x.size(0), channels = x.size(1), outChannels = g.size(1);
  const int64_t planeVec4s = x.numel() / (batch * channels) / 4;
  const bool cpu = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU;
  const int most = cpu ? kPointwiseGradChannelsCpu : kPointwiseGradChannelsGpu;
  const int inChannelsPerLane = balancedBlock(channels, most), outChannelsPerLane = balancedBlock(outChannels, most);
  const int64_t inBlocks = (channels + inChannelsPerLane - 1) / inChannelsPerLane;
  const int64_t pairs = inBlocks * ((outChannels + outChannelsPerLane - 1) / outChannelsPerLane);
  const int64_t cells = ((channels + 3) / 4) * ((outChannels + 3) / 4);
  // One subgroup per workgroup where the device allows (reductionWorkgroup); S slots per chunk otherwise.
  const uint32_t workgroup = device.reductionWorkgroup();
  const int64_t subgroups = std::max<int64_t>(workgroup / std::max(device.subgroupSize, 1u), 1);
  const int64_t wantedChunks = std::max<int64_t>(kWeightGradInvocations / (cells * batch * workgroup), 1);
  const int64_t budget = static_cast<int64_t>(kLoopIterationBudget) * workgroup;  // vec4s a chunk may hold
  const int64_t wanted = std::max(kPointwiseMinChunk * static_cast<int64_t>(workgroup),
                                  (planeVec4s + wantedChunks - 1) / wantedChunks);
  const int64_t chunkVec4s = roundUp(std::min(budget, wanted), workgroup);
  const int64_t chunks = (planeVec4s + chunkVec4s - 1) / chunkVec4s;
  const int64_t slots = batch * chunks * subgroups;
  const Tensor partial = slots == 1 ? dw : Tensor(stream.context(), {slots * dw.numel()});
  struct {
    int32_t channels, outChannels, planeVec4s, chunkVec4s, inBlocks;
    float inputSlope;
  } push{i32(channels), i32(outChannels), i32(planeVec4s), i32(chunkVec4s), i32(inBlocks), inputSlope};
  const Kernel& kernel = stream.kernel("nn/conv_pointwise_weight_grad", {workgroup, 1, 1},
                                       {inChannelsPerLane, outChannelsPerLane, inputSlope != 1.0f ? 1 : 0,
                                        cpu ? kPointwiseGradStepsCpu : kPointwiseGradStepsGpu});
  stream.dispatch(kernel, {asVec4(x), asVec4(g), partial}, push,
                  {static_cast<uint32_t>(chunks), static_cast<uint32_t>(pairs), static_cast<uint32_t>(batch)});
  if (slots > 1) sumPartials(stream, partial, slots, dw);
}

void biasGrad(Stream& stream, const Tensor& g, const Tensor& db) {
  const DeviceInfo& device = stream.context().info();
  const int64_t batch = g.size(0), channels = g.size(1);
  const int64_t plane = g.numel() / (batch * channels);
  const bool vec4s = plane % 4 == 0;
  const int64_t planeUnits = vec4s ? plane / 4 : plane;
  const uint32_t workgroup = device.reductionWorkgroup();
  const int64_t subgroups = std::max<int64_t>(workgroup / std::max(device.subgroupSize, 1u), 1);
  // A workgroup per channel; more chunks only where a lane would loop past the budget or, on a GPU, to
  // reach about kWeightGradInvocations lanes (a CPU device runs a channel per core just as fast).
  const int64_t budgetUnits = static_cast<int64_t>(kLoopIterationBudget) / batch * workgroup;
  const int64_t wantedChunks = device.type == VK_PHYSICAL_DEVICE_TYPE_CPU
                                   ? 1
                                   : std::max<int64_t>(kWeightGradInvocations / (channels * workgroup), 1);
  const int64_t wanted = (planeUnits + wantedChunks - 1) / wantedChunks;
  const int64_t chunkUnits = roundUp(std::max<int64_t>(std::min(budgetUnits, wanted), 1), workgroup);
  const int64_t chunks = (planeUnits + chunkUnits - 1) / chunkUnits;
  const int64_t slots = chunks * subgroups;
  const Tensor partial = slots == 1 ? db : Tensor(stream.context(), {slots * channels});
  struct {
    int32_t channels, batch, planeUnits, chunkUnits;
  } push{i32(channels), i32(batch), i32(planeUnits), i32(chunkUnits)};
  const Kernel& kernel = stream.kernel("nn/conv_bias_grad", {workgroup, 1, 1}, {vec4s ? 1 : 0});
  stream.dispatch(kernel, {g, vec4s ? asVec4(g) : Arg(g), partial}, push,
                  {static_cast<uint32_t>(chunks), static_cast<uint32_t>(channels), 1});
  if (slots > 1) sumPartials(stream, partial, slots, db);
}

}  // namespace smokesvd::ops::conv
