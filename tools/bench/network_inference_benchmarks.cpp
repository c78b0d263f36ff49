// Inference benchmarks of the method's networks, `infer/<network>/<preset>` for the six networks at the
// tiny, small and paper presets: one forward pass as a reconstruction runs it (pipeline/reconstruct/), with
// the architecture of the preset's built-in config, frozen (its weights packed once, networks::freeze), in
// evaluation mode, without gradients, recorded once and re-submitted. One pass is:
//   grho-coarse, grho-fine  the 16 view slots of one frame lifted into the volume, then the 3D UNet3+
//   nvref                   four views refined at once (a group of the density stage: 4 near, 6 mid, 4 far)
//   gu                      one pair of consecutive densities
//   svdiff, svdiff-init     one evaluation of the denoiser, one sample (a DDIM step is that and an update)
// FLOPs count the convolutions and linear layers (modules::FlopCounter); the weights are the initialisation's,
// since the cost depends on the architecture, not on the weights. The paper preset's passes, up to seconds
// each, are timed over 1 warm-up and at most 5 runs. Where the device cannot hold a pass the line says so
// instead of a time.
#include <memory>
#include <optional>
#include <string>

#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/networks/refiner.h"
#include "pipeline/networks/side_view_synthesizer.h"
#include "pipeline/networks/trained_model.h"
#include "pipeline/networks/velocity_generator.h"
#include "pipeline/preset.h"
#include "runtime/error.h"
#include "tools/bench/bench.h"
#include "tools/bench/network_benchmarks.h"

namespace smokesvd::bench {
namespace {

using networks::Network;

constexpr int64_t kRefinedViews = 4;

// A network ready to infer: its module (to initialise and freeze), one forward pass, and what the pass is.
struct Inference {
  modules::Module* module = nullptr;
  std::function<void(Tape&)> forward;
  std::string shape;
};

std::string imageShape(int64_t batch, int64_t channels, const Preset& p) {
  return toString(Shape{batch, channels, p.imageHeight, p.imageWidth});
}

// "a x b x c"
std::string sizes(std::initializer_list<int64_t> values) {
  std::string text;
  for (const int64_t v : values) {
    if (!text.empty()) text += 'x';
    text += std::to_string(v);
  }
  return text;
}

// The network of `config` and its inputs (constant images and densities), kept alive by the returned pass.
Inference makeInference(Context& context, const networks::NetworkConfig& config, const Preset& p) {
  const Shape volume{p.grid.z, p.grid.y, p.grid.x};
  auto image = [&](int64_t batch, int64_t channels) {
    return variable(filled(context, {batch, channels, p.imageHeight, p.imageWidth}, 0.5f));
  };
  switch (config.network) {
    case Network::GrhoCoarse:
    case Network::GrhoFine: {
      auto net = std::make_shared<networks::DensityGenerator>(
          context, models::unet3PlusFromJson(config.model, config.source), p);
      const Var images = image(p.views, 1), presence = variable(filled(context, {p.views}, 1.0f));
      return {&net->net(), [net, images, presence](Tape& tape) { net->forward(tape, images, presence); },
              std::to_string(p.views) + " views " + sizes({p.imageHeight, p.imageWidth}) + " -> " +
                  sizes({p.grid.x, p.grid.y, p.grid.z})};
    }
    case Network::NvRef: {
      auto net = std::make_shared<networks::Refiner>(context, models::unet3PlusFromJson(config.model, config.source));
      const Var images = image(kRefinedViews, 1);
      return {&net->net(), [net, images](Tape& tape) { net->forward(tape, images, images, images, images, images); },
              "5 x " + imageShape(kRefinedViews, 1, p)};
    }
    case Network::Gu: {
      auto net = std::make_shared<networks::VelocityGenerator>(
          context, models::unet3PlusFromJson(config.model, config.source), p);
      const Var density = variable(filled(context, volume, 0.5f));
      return {&net->net(), [net, density](Tape& tape) { net->forward(tape, density, density); },
              "2 densities " + sizes({p.grid.x, p.grid.y, p.grid.z})};
    }
    case Network::SvDiff:
    case Network::SvDiffInit: {
      std::shared_ptr<networks::SideViewSynthesizer> net = networks::makeSideViewSynthesizer(context, config);
      const Var noisy = image(1, net->sampleChannels()), condition = image(1, net->conditionChannels());
      const Var steps = variable(Tensor::fromHost(context, {1}, std::vector<float>{500.0f}));
      return {&net->net(), [net, noisy, condition, steps](Tape& tape) { net->predict(tape, noisy, condition, steps); },
              imageShape(1, net->sampleChannels() + net->conditionChannels(), p)};
    }
  }
  throw Error("infer: no benchmark for " + networks::networkName(config.network));
}

void measureInference(BenchContext& b, const std::string& name, Network network, const std::string& presetName) {
  Context& context = b.context();
  try {
    const Preset& p = preset(presetName);
    const Inference inference = makeInference(context, networks::defaultNetworkConfig(presetName, network), p);
    inference.module->initialize(1);
    inference.module->setTraining(false);
    networks::freeze(*inference.module);
    double flops = 0;
    {
      Stream uncounted(context);  // recorded to count, never submitted
      Tape tape(uncounted);
      const NoGrad inferring(tape);
      const modules::FlopCounter counter;
      inference.forward(tape);
      flops = counter.flops();
    }
    std::optional<LongRunTiming> timing;  // a paper-preset pass takes up to seconds; the others the usual runs
    if (presetName == "paper") timing.emplace(b);
    b.measure(name, inference.shape, 0, flops, [&](Stream& stream) {
      Tape tape(stream);
      const NoGrad inferring(tape);
      inference.forward(tape);
    });
  } catch (const Error& error) {
    addNotRun(b, name, error.what());
  } catch (const std::bad_alloc&) {
    addNotRun(b, name, "out of host memory");
  }
}

const bool registered = registerNetworkBenchmarks("infer", measureInference);

}  // namespace
}  // namespace smokesvd::bench
