// Benchmarks of the basic NN ops: the linear layer's three products (GFLOP/s, multiply and add counted
// as two), broadcast arithmetic, channel concatenation and the losses (GB/s: bytes read + written).
#include "nets/ops/broadcast.h"
#include "nets/ops/concat.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/linear.h"
#include "nets/ops/losses.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

Tensor filled(Context& context, const Shape& shape, float value) {
  Tensor tensor(context, shape);
  Stream stream(context);
  ops::fill(stream, tensor, value);
  stream.submit();
  return tensor;
}

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

const bool registered = registerBenchmark({"basic/linear", linear});

}  // namespace
}  // namespace smokesvd::bench
