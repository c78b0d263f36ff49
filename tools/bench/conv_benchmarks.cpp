// Convolution benchmarks: forward, backward-input and backward-weight of the shapes the networks spend
// their time in, each timed as the whole operation (padding and packing included). Every pass counts
// 2*N*Cout*Cin*k^d*outputs FLOPs (transposed: *inputs). The conv-blocking group times the register
// blockings side by side.
#include <string>
#include <vector>

#include "nets/ops/conv.h"
#include "nets/ops/elementwise.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

struct ConvShape {
  std::string name;   // e.g. "conv2d"
  std::string shape;  // e.g. "3x3 64->64 @ 64x64"
  Shape x;
  Shape w;
  ops::ConvParams params;
};

double flops(const ConvShape& c) {
  const Shape y = ops::convOutputShape(c.x, c.w, c.params);
  return 2.0 * static_cast<double>(numElements(y)) * static_cast<double>(numElements(c.w) / c.w[0]);
}

struct Operands {
  Tensor x, w, b, y, dy, dx, dw;
};

Operands operands(Context& context, const ConvShape& c) {
  const Shape yShape = ops::convOutputShape(c.x, c.w, c.params);
  return {filled(context, c.x, 0.5f), filled(context, c.w, 0.25f), filled(context, {c.w[0]}, 0.1f),
          Tensor(context, yShape),   filled(context, yShape, 1.0f), Tensor(context, c.x),
          Tensor(context, c.w)};
}

void passes(BenchContext& b, const ConvShape& c, const std::string& prefix, ops::ConvBlocking blocking) {
  const Operands o = operands(b.context(), c);
  const double work = flops(c);
  b.measure(prefix + "/forward", c.shape, 0, work,
            [&](Stream& s) { ops::convForward(s, o.x, o.w, &o.b, c.params, o.y, blocking); });
  b.measure(prefix + "/backward-input", c.shape, 0, work,
            [&](Stream& s) { ops::convBackwardInput(s, o.dy, o.w, c.params, o.dx, blocking); });
  b.measure(prefix + "/backward-weight", c.shape, 0, work,
            [&](Stream& s) { ops::convBackwardWeight(s, o.x, o.dy, c.params, o.dw, blocking); });
}

// Transposed convolutions (the UNets' up-sampling): x is the small input, FLOPs count every tap of every
// input position, 2*N*Cin*Cout*k^d*inputs.
void transposedPasses(BenchContext& b, const ConvShape& c) {
  const Shape yShape = ops::convTransposeOutputShape(c.x, c.w, c.params);
  const Tensor x = filled(b.context(), c.x, 0.5f), w = filled(b.context(), c.w, 0.25f);
  const Tensor bias = filled(b.context(), {c.w[1]}, 0.1f), dy = filled(b.context(), yShape, 1.0f);
  const Tensor y(b.context(), yShape), dx(b.context(), c.x), dw(b.context(), c.w);
  const double work = 2.0 * static_cast<double>(numElements(c.x)) * static_cast<double>(numElements(c.w) / c.w[0]);
  b.measure(c.name + "/forward", c.shape, 0, work,
            [&](Stream& s) { ops::convTransposeForward(s, x, w, &bias, c.params, y); });
  b.measure(c.name + "/backward-input", c.shape, 0, work,
            [&](Stream& s) { ops::convTransposeBackwardInput(s, dy, w, c.params, dx); });
  b.measure(c.name + "/backward-weight", c.shape, 0, work,
            [&](Stream& s) { ops::convTransposeBackwardWeight(s, x, dy, c.params, dw); });
}

const ConvShape kConv2d{"conv2d", "3x3 64->64 @ 64x64", {1, 64, 64, 64}, {64, 64, 3, 3}, {1, 1}};
const ConvShape kConv3d32{"conv3d", "3x3x3 32->32 @ 32^3", {1, 32, 32, 32, 32}, {32, 32, 3, 3, 3}, {1, 1}};
const ConvShape kConv3d16{"conv3d", "3x3x3 16->16 @ 64^3", {1, 16, 64, 64, 64}, {16, 16, 3, 3, 3}, {1, 1}};
const ConvShape kConv2dStrided{"conv2d-s2", "3x3 64->128 s2 @ 64x64", {1, 64, 64, 64}, {128, 64, 3, 3}, {2, 1}};

const ConvShape kTranspose2d{"conv-transpose2d", "2x2 s2 64->32 @ 32x32", {1, 64, 32, 32}, {64, 32, 2, 2}, {2, 0}};
const ConvShape kTranspose3d{"conv-transpose3d", "2x2x2 s2 32->16 @ 16^3", {1, 32, 16, 16, 16}, {32, 16, 2, 2, 2},
                             {2, 0}};

// The convolutions of the small G_rho (32x56x32 volumes; docs/benchmarks.md, train benchmarks): the stem,
// the 3x3x3 convolutions of a bottleneck at 12 and at 4 channels, its 1x1x1 convolutions and the stride-2
// pair of a down-sampling block.
const std::vector<ConvShape> kNetworkShapes{
    {"conv-net/stem", "3x3x3 16->12 @ 32x56x32", {1, 16, 32, 56, 32}, {12, 16, 3, 3, 3}, {1, 1}},
    {"conv-net/3x3x3-12", "3x3x3 12->12 @ 32x56x32", {1, 12, 32, 56, 32}, {12, 12, 3, 3, 3}, {1, 1}},
    {"conv-net/3x3x3-4", "3x3x3 4->4 @ 32x56x32", {1, 4, 32, 56, 32}, {4, 4, 3, 3, 3}, {1, 1}},
    {"conv-net/1x1x1-48", "1x1x1 48->48 @ 32x56x32", {1, 48, 32, 56, 32}, {48, 48, 1, 1, 1}, {1, 0}},
    {"conv-net/1x1x1-48-12", "1x1x1 48->12 @ 32x56x32", {1, 48, 32, 56, 32}, {12, 48, 1, 1, 1}, {1, 0}},
    {"conv-net/1x1x1-12-48", "1x1x1 12->48 @ 32x56x32", {1, 12, 32, 56, 32}, {48, 12, 1, 1, 1}, {1, 0}},
    {"conv-net/1x1x1-48-1", "1x1x1 48->1 @ 32x56x32", {1, 48, 32, 56, 32}, {1, 48, 1, 1, 1}, {1, 0}},
    {"conv-net/2x2x2-s2", "2x2x2 s2 12->24 @ 32x56x32", {1, 12, 32, 56, 32}, {24, 12, 2, 2, 2}, {2, 0}},
    {"conv-net/3x3x3-s2", "3x3x3 s2 6->6 @ 32x56x32", {1, 6, 32, 56, 32}, {6, 6, 3, 3, 3}, {2, 1}},
};

void blockings(BenchContext& b) {
  for (const ConvShape* c : {&kConv2d, &kConv3d32}) {
    const Operands o = operands(b.context(), *c);
    for (ops::ConvBlocking blocking : {ops::ConvBlocking{4, 1}, ops::ConvBlocking{8, 1}, ops::ConvBlocking{16, 1},
                                       ops::ConvBlocking{4, 2}, ops::ConvBlocking{8, 2}, ops::ConvBlocking{16, 2},
                                       ops::ConvBlocking{8, 3}, ops::ConvBlocking{8, 4}}) {
      const std::string tag = std::to_string(blocking.pixels) + "x" + std::to_string(blocking.channelVec4s * 4);
      b.measure("conv-blocking/" + c->name + "-forward-" + tag, c->shape, 0, flops(*c),
                [&](Stream& s) { ops::convForward(s, o.x, o.w, &o.b, c->params, o.y, blocking); });
      b.measure("conv-blocking/" + c->name + "-weight-" + tag, c->shape, 0, flops(*c),
                [&](Stream& s) { ops::convBackwardWeight(s, o.x, o.dy, c->params, o.dw, blocking); });
    }
  }
}

// The pointwise kernel's blockings (position vec4s x output channels) on the small G_rho's 1x1x1 shapes
// with more than one output channel (a single channel leaves nothing to block).
void pointwiseBlockings(BenchContext& b) {
  const std::string group = "conv-net/";
  for (const ConvShape& c : kNetworkShapes) {
    const bool pointwise = numElements(c.w) == c.w[0] * c.w[1];
    if (!pointwise || c.w[0] == 1) continue;
    const Operands o = operands(b.context(), c);
    const std::string name = c.name.substr(group.size());  // e.g. "1x1x1-48"
    for (ops::ConvBlocking blocking : {ops::ConvBlocking{4, 1}, ops::ConvBlocking{8, 1}, ops::ConvBlocking{16, 1},
                                       ops::ConvBlocking{4, 2}, ops::ConvBlocking{8, 2}, ops::ConvBlocking{16, 2},
                                       ops::ConvBlocking{4, 3}, ops::ConvBlocking{4, 4}, ops::ConvBlocking{8, 4}}) {
      const std::string tag = std::to_string(blocking.pixels / 4) + "x" + std::to_string(blocking.channelVec4s * 4);
      b.measure("conv-blocking/" + name + "-forward-" + tag, c.shape, 0, flops(c),
                [&](Stream& s) { ops::convForward(s, o.x, o.w, &o.b, c.params, o.y, blocking); });
      b.measure("conv-blocking/" + name + "-backward-input-" + tag, c.shape, 0, flops(c),
                [&](Stream& s) { ops::convBackwardInput(s, o.dy, o.w, c.params, o.dx, blocking); });
    }
  }
}

const bool registered =
    registerBenchmark({"conv/2d-3x3-64", [](BenchContext& b) { passes(b, kConv2d, "conv2d", {}); }}) &&
    registerBenchmark({"conv/2d-3x3-64-stride2", [](BenchContext& b) { passes(b, kConv2dStrided, "conv2d-s2", {}); }}) &&
    registerBenchmark({"conv/3d-3x3x3-32", [](BenchContext& b) { passes(b, kConv3d32, "conv3d", {}); }}) &&
    registerBenchmark({"conv/3d-3x3x3-16", [](BenchContext& b) { passes(b, kConv3d16, "conv3d", {}); }}) &&
    registerBenchmark({"conv/transpose2d-2x2", [](BenchContext& b) { transposedPasses(b, kTranspose2d); }}) &&
    registerBenchmark({"conv/transpose3d-2x2x2", [](BenchContext& b) { transposedPasses(b, kTranspose3d); }}) &&
    registerBenchmark({"conv-blocking/sweep", blockings}) &&
    registerBenchmark({"conv-blocking/pointwise", pointwiseBlockings}) &&
    registerBenchmark({"conv-net/grho-small", [](BenchContext& b) {
                         for (const ConvShape& c : kNetworkShapes) passes(b, c, c.name, {});
                       }});

}  // namespace
}  // namespace smokesvd::bench
