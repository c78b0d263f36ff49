// Training-step benchmarks: forward, loss, backward and Adam of a network, recorded once and submitted
// again and again, each with the memory its recording holds and the pool's peak (BenchContext::measureStep),
// once with buffer reuse within the recording (the default) and once without (docs/runtime.md). FLOPs
// count the convolutions: forward, backward-input and backward-weight, 2*N*Cout*Cin*k^3*voxels each (for
// the conv3d stack exactly, without the first layer's backward-input, whose input needs no gradient; for
// the UNet3+ as three times its forward's, modules::FlopCounter).
#include <memory>
#include <string>

#include "nets/functional/losses.h"
#include "nets/models/unet3plus.h"
#include "nets/modules/activation.h"
#include "nets/modules/conv.h"
#include "nets/modules/flop_counter.h"
#include "nets/modules/module.h"
#include "nets/optim/adam.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

// Five 3x3x3 convolutions 4 -> 16 -> 16 -> 16 -> 16 -> 1 with SiLU between, on a 32^3 volume.
constexpr int64_t kSide = 32;
constexpr int64_t kChannels[] = {4, 16, 16, 16, 16, 1};

void conv3dStack(BenchContext& b) {
  Context& context = b.context();
  auto net = std::make_shared<modules::Sequential>();
  const int64_t voxels = kSide * kSide * kSide;
  double flops = 0;
  for (std::size_t layer = 0; layer + 1 < std::size(kChannels); ++layer) {
    if (layer > 0) net->add(std::make_shared<modules::Activation>(modules::ActivationKind::SiLU));
    net->add(std::make_shared<modules::Conv>(context, 3, kChannels[layer], kChannels[layer + 1], 3,
                                             modules::ConvOptions{1, 1}));
    flops += (layer > 0 ? 3.0 : 2.0) * 2.0 * static_cast<double>(kChannels[layer] * kChannels[layer + 1] * 27 * voxels);
  }
  net->initialize(1);
  const Var x = variable(filled(context, {1, kChannels[0], kSide, kSide, kSide}, 0.5f));
  const Var target = variable(filled(context, {1, 1, kSide, kSide, kSide}, 0.25f));
  const optim::Adam adam(context, net->namedParameters(), optim::AdamOptions{});
  const std::string shape = "5 conv3d 3^3 4-16-16-16-16-1 @ 32^3";
  for (const bool reuse : {true, false}) {
    b.measureStep(reuse ? "train/conv3d-stack" : "train/conv3d-stack-no-reuse", shape, flops,
                  {.reuseBuffers = reuse}, [&](Stream& stream) {
                    clearGradients(net->namedParameters());  // each recording computes its own
                    Tape tape(stream);
                    tape.backward(fn::mseLoss(tape, net->forward(tape, x), target));
                    adam.step(stream);
                  });
  }
}

// The 3D UNet3+ of G_rho at its default widths (filters 8-16-32-64, 8 channels per decoder source) on
// four views lifted into a 32^3 volume, one sample.
void unet3plus(BenchContext& b) {
  Context& context = b.context();
  models::UNet3PlusConfig config;
  config.inChannels = 4;
  models::UNet3Plus net(context, config);
  net.initialize(1);
  const Var x = variable(filled(context, {1, config.inChannels, kSide, kSide, kSide}, 0.5f));
  const Var target = variable(filled(context, {1, config.outChannels, kSide, kSide, kSide}, 0.25f));
  const optim::Adam adam(context, net.namedParameters(), optim::AdamOptions{});
  double flops = 0;
  {
    const modules::FlopCounter counter;
    Stream uncounted(context);  // recorded to count, never submitted
    Tape tape(uncounted);
    const NoGrad inference(tape);
    net.forward(tape, x);
    flops = 3 * counter.flops();
  }
  for (const bool reuse : {true, false}) {
    b.measureStep(reuse ? "train/unet3plus-3d" : "train/unet3plus-3d-no-reuse", "filters 8-16-32-64 c8, 4 in @ 32^3",
                  flops, {.reuseBuffers = reuse}, [&](Stream& stream) {
                    clearGradients(net.namedParameters());
                    Tape tape(stream);
                    tape.backward(fn::mseLoss(tape, net.forward(tape, x).output, target));
                    adam.step(stream);
                  });
  }
}

const bool registered = registerBenchmark({"train/conv3d-stack", conv3dStack}) &&
                        registerBenchmark({"train/unet3plus-3d", unet3plus});

}  // namespace
}  // namespace smokesvd::bench
