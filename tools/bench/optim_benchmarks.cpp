// Optimiser benchmarks: Adam over 10 M parameters (one tensor, and the same split into 100 tensors to
// show the per-tensor dispatch cost), the global gradient norm of clipping, and the EMA update. Bytes
// count everything read plus everything written: Adam reads p, g, m, v and writes p, m, v (28 bytes per
// parameter); the norm reads g (4); the EMA reads shadow and p and writes shadow (12). Then the whole
// update of a training step (norm, clipped AdamW, EMA) over the parameters of two small-preset networks,
// a UNet3+ of many small tensors and a DDPM UNet with some large ones: what the per-dispatch cost does to
// real parameter lists.
#include "nets/models/model_json.h"
#include "nets/ops/elementwise.h"
#include "nets/optim/adam.h"
#include "nets/optim/ema.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/side_view_synthesizer.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

constexpr int64_t kParameters = 10'000'000;

// `pieces` parameter tensors of kParameters / pieces elements each, with gradients filled in.
NamedParameters parameters(Context& context, int64_t pieces) {
  NamedParameters named;
  Stream fill(context);
  for (int64_t i = 0; i < pieces; ++i) {
    Var p = variable(Tensor(context, {kParameters / pieces}), true);
    p->grad = Tensor(context, {kParameters / pieces});
    ops::fill(fill, p->value, 0.5f);
    ops::fill(fill, p->grad, 1e-3f);
    named.emplace_back("layer" + std::to_string(i) + ".weight", p);
  }
  fill.submit();
  return named;
}

void adam(BenchContext& b) {
  for (const int64_t pieces : {int64_t{1}, int64_t{100}}) {
    const NamedParameters named = parameters(b.context(), pieces);
    const std::string shape = pieces == 1 ? "[10000000]" : "100 x [100000]";
    const optim::Adam adamOptimizer(b.context(), named, optim::AdamOptions{});
    b.measure(pieces == 1 ? "optim/adam" : "optim/adam-100-tensors", shape, 28.0 * kParameters, 0,
              [&](Stream& s) { adamOptimizer.step(s); });
    if (pieces != 1) continue;
    const optim::Adam adamW(b.context(), named, optim::AdamOptions::adamW(optim::LrSchedule::constant(1e-3)));
    const optim::GradClip clip(b.context(), 1.0);
    b.measure("optim/adamw-clipped", shape + ", norm + AdamW", 32.0 * kParameters, 0, [&](Stream& s) {
      clip.record(s, named);
      adamW.step(s, &clip);
    });
    b.measure("optim/grad-norm", shape, 4.0 * kParameters, 2.0 * kParameters,
              [&](Stream& s) { clip.record(s, named); });
    const optim::Ema ema(b.context(), named, 0.999);
    b.measure("optim/ema", shape, 12.0 * kParameters, 3.0 * kParameters, [&](Stream& s) { ema.update(s); });
  }
}

// Gradients for every parameter of `module`, and the update a training step records after its backward pass.
void measureUpdate(BenchContext& b, const std::string& name, modules::Module& module) {
  const NamedParameters named = module.namedParameters();
  Stream fill(b.context());
  int64_t count = 0;
  for (const auto& [parameterName, p] : named) {
    p->grad = Tensor(b.context(), p->value.shape());
    ops::fill(fill, p->grad, 1e-3f);
    count += p->value.numel();
  }
  fill.submit();
  const optim::Adam adamW(b.context(), named, optim::AdamOptions::adamW(optim::LrSchedule::constant(1e-3)));
  const optim::GradClip clip(b.context(), 1.0);
  const optim::Ema ema(b.context(), named, 0.999);
  b.measure(name, std::to_string(named.size()) + " tensors, " + std::to_string(count) + " parameters",
            44.0 * static_cast<double>(count), 0, [&](Stream& s) {
              clip.record(s, named);
              adamW.step(s, &clip);
              ema.update(s);
            });
}

void trainingUpdates(BenchContext& b) {
  const networks::NetworkConfig grho = networks::defaultNetworkConfig("small", networks::Network::GrhoCoarse);
  networks::DensityGenerator generator(b.context(), models::unet3PlusFromJson(grho.model, grho.source), preset("small"));
  measureUpdate(b, "optim/update-grho-small", generator.net());
  const networks::NetworkConfig svdiff = networks::defaultNetworkConfig("small", networks::Network::SvDiff);
  const auto synthesizer = networks::makeSideViewSynthesizer(b.context(), svdiff);
  measureUpdate(b, "optim/update-svdiff-small", synthesizer->net());
}

const bool registered = registerBenchmark({"optim", adam}) && registerBenchmark({"optim-update", trainingUpdates});

}  // namespace
}  // namespace smokesvd::bench
