// Benchmarks of the basic NN ops: the linear layer's three products (GFLOP/s, multiply and add counted
// as two), broadcast arithmetic, channel concatenation and the losses (GB/s: bytes read + written).
#include "nets/ops/broadcast.h"
#include "nets/ops/concat.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/linear.h"
#include "nets/ops/losses.h"
#include "nets/ops/reduce_axes.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

void linear(BenchContext& b) {
  constexpr int64_t kBatch = 256, kIn = 1024, kOut = 1024;
  Context& c = b.context();
  const Tensor x = filled(c, {kBatch, kIn}, 0.5f), w = filled(c, {kOut, kIn}, 0.25f), bias = filled(c, {kOut}, 1.0f);
  const Tensor y(c, {kBatch, kOut}), gy = filled(c, {kBatch, kOut}, 1.0f), gx(c, x.shape()), gw(c, w.shape());
  const std::string shape = "1024->1024 @ batch 256";
  const double flops = 2.0 * kBatch * kIn * kOut;
  b.measure("basic/linear-forward", shape, 0, flops, [&](Stream& s) { ops::linearForward(s, x, w, &bias, y); });
  b.measure("basic/linear-backward-input", shape, 0, flops, [&](Stream& s) { ops::linearBackwardInput(s, gy, w, gx); });
  b.measure("basic/linear-backward-weight", shape, 0, flops,
            [&](Stream& s) { ops::linearBackwardWeight(s, gy, x, gw); });
}

double bytes(std::initializer_list<const Tensor*> tensors) {
  double total = 0;
  for (const Tensor* tensor : tensors) total += static_cast<double>(tensor->bytes());
  return total;
}

// Per-channel bias add, per-sample scale, and the bias gradient (sum over N, H, W) on a UNet-sized map.
void broadcast(BenchContext& b) {
  Context& c = b.context();
  const Tensor x = filled(c, {8, 64, 64, 64}, 1.0f), y(c, x.shape());
  const Tensor channel = filled(c, {1, 64, 1, 1}, 0.5f), sample = filled(c, {8, 1, 1, 1}, 2.0f), gb(c, {64});
  const std::string shape = "[8, 64, 64, 64]";
  b.measure("basic/add-same-shape (baseline)", shape + " + " + shape, bytes({&x, &x, &y}), static_cast<double>(x.numel()),
            [&](Stream& s) { ops::add(s, x, x, y); });
  b.measure("basic/broadcast-add-channel", shape + " + [1, 64, 1, 1]", bytes({&x, &channel, &y}), static_cast<double>(x.numel()),
            [&](Stream& s) { ops::broadcastBinary(s, ops::BinaryOp::Add, x, channel, y); });
  b.measure("basic/broadcast-mul-sample", shape + " * [8, 1, 1, 1]", bytes({&x, &sample, &y}), static_cast<double>(x.numel()),
            [&](Stream& s) { ops::broadcastBinary(s, ops::BinaryOp::Mul, x, sample, y); });
  b.measure("basic/expand-channel", "[1, 64, 1, 1] -> " + shape, bytes({&channel, &y}), 0,
            [&](Stream& s) { ops::expand(s, channel, y); });
  const std::vector<int> axes{0, 2, 3};
  b.measure("basic/sum-axes-bias-grad", shape + " over 0,2,3", bytes({&x, &gb}), static_cast<double>(x.numel()),
            [&](Stream& s) { ops::reduceAxes(s, ops::ReduceMap::Identity, x, nullptr, axes, 1.0f, gb); });
}

// Skip-connection concatenation of two [8, 32, 64, 64] maps, and the slice its backward takes.
void concat(BenchContext& b) {
  Context& c = b.context();
  const std::vector<Tensor> halves{filled(c, {8, 32, 64, 64}, 1.0f), filled(c, {8, 32, 64, 64}, 2.0f)};
  const Tensor y(c, {8, 64, 64, 64}), slice(c, {8, 32, 64, 64});
  b.measure("basic/concat-channels", "2 x [8, 32, 64, 64]", 2 * bytes({&y}), 0,
            [&](Stream& s) { ops::concatChannels(s, halves, y); });
  b.measure("basic/slice-channels", "[8, 64, 64, 64][:, 32:64]", 2 * bytes({&slice}), 0,
            [&](Stream& s) { ops::sliceChannels(s, y, 32, 64, slice); });
}

// The NvRef / SvDiff losses on a batch of 16 single-channel 112 x 64 images, forward and backward.
void losses(BenchContext& b) {
  Context& c = b.context();
  const Shape shape{16, 1, 112, 64};
  const Tensor a = filled(c, shape, 0.25f), r = filled(c, shape, 0.5f), ga(c, shape);
  const Tensor loss(c, {1}), g = filled(c, {1}, 1.0f), rows(c, {16 * 112}), mseA(c, {16}), mseB(c, {16}), mean(c, {1});
  const std::string text = "[16, 1, 112, 64]";
  const double two = bytes({&a, &r}), three = bytes({&a, &r, &ga});
  b.measure("basic/mse-loss", text, two, 0, [&](Stream& s) { ops::mseLoss(s, a, r, loss); });
  b.measure("basic/mse-loss-backward", text, three, 0, [&](Stream& s) { ops::mseLossBackward(s, g, a, r, ga); });
  b.measure("basic/l1-loss", text, two, 0, [&](Stream& s) { ops::l1Loss(s, a, r, loss); });
  b.measure("basic/l1-loss-backward", text, three, 0, [&](Stream& s) { ops::l1LossBackward(s, g, a, r, ga); });
  b.measure("basic/row-sum-loss", text, two, 0, [&](Stream& s) { ops::rowSumLoss(s, a, r, rows, loss); });
  b.measure("basic/row-sum-loss-backward", text, bytes({&ga}), 0,
            [&](Stream& s) { ops::rowSumLossBackward(s, g, rows, ga); });
  b.measure("basic/psnr", text, two, 0, [&](Stream& s) {
    ops::sampleMse(s, a, r, mseA);
    ops::psnr(s, mseA, {}, loss);
  });
  b.measure("basic/psnr-gap-loss", text + " x 3", 4 * bytes({&a}), 0, [&](Stream& s) {
    ops::sampleMse(s, a, r, mseA);
    ops::sampleMse(s, r, a, mseB);
    ops::psnrGap(s, mseA, mseB, {}, loss);
  });
  b.measure("basic/mean-residual-squared", text, bytes({&a}), 0,
            [&](Stream& s) { ops::meanResidualSquared(s, a, mean, loss); });
}

const bool registered = registerBenchmark({"basic/linear", linear}) && registerBenchmark({"basic/broadcast", broadcast}) &&
                        registerBenchmark({"basic/concat", concat}) && registerBenchmark({"basic/losses", losses});

}  // namespace
}  // namespace smokesvd::bench
