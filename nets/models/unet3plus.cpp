#include "nets/models/unet3plus.h"

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/functional/pool.h"
#include "nets/functional/resample.h"
#include "runtime/context.h"
#include "runtime/error.h"

namespace smokesvd::models {

void UNet3PlusConfig::validate() const {
  if (dims != 2 && dims != 3) throw Error("UNet3+ config: dims must be 2 or 3, got " + std::to_string(dims));
  if (inChannels <= 0) throw Error("UNet3+ config: in_channels must be positive");
  if (outChannels <= 0) throw Error("UNet3+ config: out_channels must be positive");
  if (filters.size() < 2) throw Error("UNet3+ config: filters must list at least 2 levels");
  for (const int64_t f : filters)
    if (f <= 0) throw Error("UNet3+ config: every filters entry must be positive");
  if (catChannels <= 0) throw Error("UNet3+ config: cat_channels must be positive");
  if (minMid <= 0) throw Error("UNet3+ config: min_mid must be positive");
  if (presenceSlots < 0) throw Error("UNet3+ config: presence_slots must be >= 0");
}

UNet3Plus::UNet3Plus(Context& context, UNet3PlusConfig config)
    : config_(std::move(config)), largestTensorBytes_(context.info().maxTensorBytes()) {
  config_.validate();
  const UNet3PlusConfig& c = config_;
  const int levels = c.levels();
  const int64_t fused = c.catChannels * levels;
  auto block = [&](int64_t in, int64_t out, bool down) {
    return std::make_shared<Bottleneck>(context, BottleneckOptions{c.dims, in, out, down, c.minMid, c.negativeSlope});
  };

  stem_ = addChild("stem", std::make_shared<modules::Conv>(context, c.dims, c.inChannels, c.filters[0], 3,
                                                           modules::ConvOptions{1, 1, true, modules::WeightInit::Lecun}));
  if (c.presenceSlots > 0)
    presence_ = addChild("presence", std::make_shared<modules::Linear>(context, c.presenceSlots, c.filters[0], true,
                                                                       modules::WeightInit::Lecun));

  auto down = addChild("down", std::make_shared<modules::ModuleList>());
  for (int l = 1; l < levels; ++l) down_.push_back(down->add(block(c.filters[l - 1], c.filters[l], true)));

  // decoder.<d>: stages from the deepest (d = L-2) to the finest (d = 0), listed by d.
  auto decoder = addChild("decoder", std::make_shared<modules::ModuleList>());
  sources_.resize(static_cast<std::size_t>(levels - 1));
  for (int d = 0; d < levels - 1; ++d) {
    auto stage = decoder->add(std::make_shared<modules::ModuleList>());
    // Sources by level; a decoder map hd_s (d < s < L-1) carries L c channels.
    for (int s = 0; s < levels; ++s) {
      const int64_t in = (s > d && s < levels - 1) ? fused : c.filters[static_cast<std::size_t>(s)];
      sources_[static_cast<std::size_t>(d)].push_back(stage->add(block(in, c.catChannels, false)));
    }
    fuse_.push_back(stage->add(block(fused, fused, false)));
  }

  auto heads = addChild("heads", std::make_shared<modules::ModuleList>());
  for (int k = 0; k < levels; ++k) {
    const int64_t in = k < levels - 1 ? fused : c.filters.back();
    heads_.push_back(heads->add(std::make_shared<modules::Conv>(context, c.dims, in, c.outChannels, 1,
                                                                modules::ConvOptions{1, 0, true, modules::WeightInit::Lecun})));
  }
}

Var UNet3Plus::source(Tape& tape, int stage, int level, const std::vector<Var>& encoder,
                      const std::vector<Parts>& decoder) {
  const int levels = config_.levels();
  const auto& block = sources_[static_cast<std::size_t>(stage)][static_cast<std::size_t>(level)];
  if (level <= stage) {
    Var x = encoder[static_cast<std::size_t>(level)];
    for (int k = level; k < stage; ++k) x = fn::maxPool(tape, x);
    return block->forward(tape, x);
  }
  const Parts deeper = level == levels - 1 ? Parts{encoder.back()} : decoder[static_cast<std::size_t>(level)];
  return fn::upsample(tape, block->forwardParts(tape, deeper, {config_.catChannels})[0], 1 << (level - stage),
                      fn::ResampleMode::Linear);
}

UNet3PlusOutput UNet3Plus::forward(Tape& tape, const Var& x, const Var& presence, bool deepSupervision) {
  const UNet3PlusConfig& c = config_;
  const int levels = c.levels();
  if (x->value.rank() != c.dims + 2 || x->value.size(1) != c.inChannels)
    throw Error("UNet3+: input of shape " + toString(x->value.shape()) + ", expected [N, " +
                std::to_string(c.inChannels) + ", " + (c.dims == 3 ? "D, H, W]" : "H, W]"));
  const int64_t divisor = int64_t{1} << (levels - 1);
  for (int axis = 2; axis < x->value.rank(); ++axis)
    if (x->value.size(axis) % divisor != 0)
      throw Error("UNet3+: input of shape " + toString(x->value.shape()) + ": every spatial size must be divisible by " +
                  std::to_string(divisor) + " (2^(levels - 1))");
  if ((c.presenceSlots > 0) != static_cast<bool>(presence))
    throw Error(c.presenceSlots > 0 ? "UNet3+: built with presence slots, called without a presence vector"
                                    : "UNet3+: called with a presence vector it was not built for");

  std::vector<Var> encoder;
  Var h = stem_->forward(tape, x);
  if (presence_) {
    if (presence->value.numel() != x->value.size(0) * c.presenceSlots)
      throw Error("UNet3+: presence of shape " + toString(presence->value.shape()) + ", expected [N, " +
                  std::to_string(c.presenceSlots) + "]");
    h = fn::addChannel(tape, h, presence_->forward(tape, fn::reshape(tape, presence, {x->value.size(0), c.presenceSlots})));
  }
  encoder.push_back(h);
  for (const auto& block : down_) encoder.push_back(block->forward(tape, encoder.back()));

  std::vector<Parts> decoder(static_cast<std::size_t>(levels - 1));
  for (int d = levels - 2; d >= 0; --d) {
    Parts sources;
    for (int s = 0; s < levels; ++s) sources.push_back(source(tape, d, s, encoder, decoder));
    const Tensor& level = encoder[static_cast<std::size_t>(d)]->value;
    const uint64_t fusedBytes = static_cast<uint64_t>(level.numel() / level.size(1)) *
                                static_cast<uint64_t>(c.catChannels * levels) * sizeof(float);
    const auto& fuse = fuse_[static_cast<std::size_t>(d)];
    decoder[static_cast<std::size_t>(d)] =
        fusedBytes > largestTensorBytes_
            ? fuse->forwardParts(tape, sources, std::vector<int64_t>(static_cast<std::size_t>(levels), c.catChannels))
            : Parts{fuse->forward(tape, fn::concatChannels(tape, sources))};
  }

  auto head = [&](int k, const Parts& map) {
    Var y = heads_[static_cast<std::size_t>(k)]->forwardParts(tape, map, {c.outChannels})[0];
    return c.output == OutputActivation::ReLU ? fn::relu(tape, y) : y;
  };
  UNet3PlusOutput result;
  result.output = head(0, decoder[0]);
  if (deepSupervision)
    for (int k = 1; k < levels; ++k) {
      const Parts map = k < levels - 1 ? decoder[static_cast<std::size_t>(k)] : Parts{encoder.back()};
      result.supervision.push_back(fn::upsample(tape, head(k, map), 1 << k, fn::ResampleMode::Nearest));
    }
  return result;
}

}  // namespace smokesvd::models
