// NN layer benchmarks: GroupNorm, trilinear resampling, 3D pooling, activations, dropout. Bytes count
// each tensor an op must touch once (inputs read, outputs written), not the extra passes a kernel makes:
// GroupNorm forward = x + y, backward = x + gy + gx; so GB/s compares with a copy's.
#include "nets/ops/activation.h"
#include "nets/ops/dropout.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/group_norm.h"
#include "nets/ops/pool.h"
#include "nets/ops/resample.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

// Values scattered over [-1, 1) (a multiplicative hash of the index), so max-pool windows are not ties.
Tensor varied(Context& context, const Shape& shape) {
  std::vector<float> values(static_cast<std::size_t>(numElements(shape)));
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = static_cast<float>((i * 2654435761u) % 1000) / 500.0f - 1.0f;
  return Tensor::fromHost(context, shape, values);
}

double bytesOf(const Shape& shape, double tensors) { return static_cast<double>(numElements(shape)) * 4.0 * tensors; }

// The norm alone and the norm followed by SiLU in the same pass ("-silu").
void groupNorm(BenchContext& b, const Shape& shape, int64_t groups, ops::NormActivation activation) {
  Context& context = b.context();
  const Shape c{shape[1]};
  const Tensor x = varied(context, shape);
  const Tensor gamma = filled(context, c, 1.0f), beta = filled(context, c, 0.0f);
  const Tensor gy = varied(context, shape);
  Tensor y(context, shape), gx(context, shape), ggamma(context, c), gbeta(context, c);
  Tensor stats(context, {shape[0] * groups, 2});
  const std::string label = toString(shape) + " G=" + std::to_string(groups);
  const std::string name = "layers/group_norm-" + std::to_string(shape.size() - 2) + "d" +
                           (activation == ops::NormActivation::Silu ? "-silu" : "");
  auto forward = [&](Stream& s) { ops::groupNormForward(s, x, gamma, beta, groups, 1e-5f, y, stats, activation); };
  auto backward = [&](Stream& s) {
    ops::groupNormBackward(s, x, gamma, beta, stats, groups, gy, gx, ggamma, gbeta, activation);
  };
  b.measure(name + "/forward", label, bytesOf(shape, 2), 0, forward);
  {
    Stream once(context);
    forward(once);
    once.submit();
  }
  b.measure(name + "/backward", label, bytesOf(shape, 3), 0, backward);
  b.measure(name + "/forward+backward", label, bytesOf(shape, 5), 0, [&](Stream& s) {
    forward(s);
    backward(s);
  });
}

void groupNorms(BenchContext& b) {
  for (const ops::NormActivation activation : {ops::NormActivation::None, ops::NormActivation::Silu}) {
    groupNorm(b, {1, 64, 64, 64}, 8, activation);
    groupNorm(b, {1, 32, 32, 32, 32}, 8, activation);
  }
}

void trilinear(BenchContext& b) {
  const Shape in{1, 32, 32, 32, 32};
  const ops::Resample up{ops::ResampleMode::Linear, false, 2};
  const Shape out = ops::resampledShape(in, up);
  const Tensor x = varied(b.context(), in), gy = varied(b.context(), out);
  Tensor y(b.context(), out), gx(b.context(), in);
  const double bytes = bytesOf(in, 1) + bytesOf(out, 1);
  const std::string label = toString(in) + " x2";
  b.measure("layers/trilinear-up/forward", label, bytes, 0, [&](Stream& s) { ops::resampleForward(s, up, x, y); });
  b.measure("layers/trilinear-up/backward", label, bytes, 0, [&](Stream& s) { ops::resampleBackward(s, up, gy, gx); });
  b.measure("layers/trilinear-up/forward+backward", label, 2 * bytes, 0, [&](Stream& s) {
    ops::resampleForward(s, up, x, y);
    ops::resampleBackward(s, up, gy, gx);
  });
  const ops::Resample down{ops::ResampleMode::Linear, true, 2};
  Tensor small(b.context(), in);
  b.measure("layers/trilinear-down/forward", toString(out) + " /2", bytes, 0,
            [&](Stream& s) { ops::resampleForward(s, down, y, small); });
}

void pooling(BenchContext& b) {
  const Shape in{1, 32, 64, 64, 64};
  const Shape out = ops::pooledShape(in);
  const Tensor x = varied(b.context(), in), gy = varied(b.context(), out);
  Tensor y(b.context(), out), gx(b.context(), in);
  const std::string label = toString(in);
  for (const auto& [kind, tag] : {std::pair{ops::PoolKind::Max, "max"}, std::pair{ops::PoolKind::Average, "avg"}}) {
    b.measure("layers/" + std::string(tag) + "-pool-3d/forward", label, bytesOf(in, 1) + bytesOf(out, 1), 0,
              [&, kind = kind](Stream& s) { ops::poolForward(s, kind, x, y); });
    // max-pool backward reads x, gy and writes gx; average pooling does not read x
    const double backwardBytes = bytesOf(in, kind == ops::PoolKind::Max ? 2 : 1) + bytesOf(out, 1);
    b.measure("layers/" + std::string(tag) + "-pool-3d/backward", label, backwardBytes, 0,
              [&, kind = kind](Stream& s) { ops::poolBackward(s, kind, x, gy, gx); });
  }
}

void pointwise(BenchContext& b) {
  const Shape shape{1, 64, 64, 64};
  const Tensor x = varied(b.context(), shape), gy = varied(b.context(), shape);
  Tensor y(b.context(), shape), gx(b.context(), shape);
  const std::string label = toString(shape);
  b.measure("layers/silu/forward", label, bytesOf(shape, 2), 0,
            [&](Stream& s) { ops::activationForward(s, ops::Activation::Silu, 0.0f, x, y); });
  b.measure("layers/silu/backward", label, bytesOf(shape, 3), 0,
            [&](Stream& s) { ops::activationBackward(s, ops::Activation::Silu, 0.0f, x, gy, gx); });
  b.measure("layers/dropout", label, bytesOf(shape, 2), 0, [&](Stream& s) { ops::dropout(s, x, 0.1f, 1, y); });
}

const bool registered =
    registerBenchmark({"layers/group_norm", groupNorms}) && registerBenchmark({"layers/resample", trilinear}) &&
    registerBenchmark({"layers/pool", pooling}) && registerBenchmark({"layers/pointwise", pointwise});

}  // namespace
}  // namespace smokesvd::bench
