#include "nets/models/ddpm_unet.h"

#include "nets/functional/activation.h"
#include "nets/functional/concat.h"
#include "nets/functional/resample.h"
#include "nets/functional/timestep_embedding.h"
#include "runtime/error.h"

namespace smokesvd::models {
namespace {

// A module that only names its children (PyTorch's bare nn.Module() holders: temb, down.i, mid, ...).
class Holder : public modules::Module {
 public:
  using Module::addChild;
};

}  // namespace

void DdpmUNetConfig::validate() const {
  if (inChannels <= 0) throw Error("DDPM UNet config: in_channels must be positive");
  if (outChannels <= 0) throw Error("DDPM UNet config: out_channels must be positive");
  if (channels <= 0) throw Error("DDPM UNet config: channels must be positive");
  if (channelMult.empty()) throw Error("DDPM UNet config: channel_mult must list at least one level");
  if (resBlocks <= 0) throw Error("DDPM UNet config: res_blocks must be positive");
  if (groups <= 0) throw Error("DDPM UNet config: groups must be positive");
  if (channels % groups != 0) throw Error("DDPM UNet config: groups must divide channels");
  for (const int64_t m : channelMult)
    if (m <= 0 || (channels * m) % groups != 0)
      throw Error("DDPM UNet config: every channel_mult entry must be positive and channels * mult divisible by groups");
  if (!(dropout >= 0.0f && dropout < 1.0f)) throw Error("DDPM UNet config: dropout must be in [0, 1)");
}

DdpmUNet::DdpmUNet(Context& context, DdpmUNetConfig config) : config_(std::move(config)) {
  config_.validate();
  const DdpmUNetConfig& c = config_;
  const int levels = c.levels();
  const int64_t tembChannels = 4 * c.channels;
  auto resBlock = [&](int64_t in, int64_t out) {
    modules::ResBlockOptions o;
    o.dims = 2;
    o.inChannels = in;
    o.outChannels = out;
    o.tembChannels = tembChannels;
    o.groups = c.groups;
    o.dropout = c.dropout;
    return std::make_shared<modules::ResBlock>(context, o);
  };
  auto conv3 = [&](int64_t in, int64_t out, int stride, modules::WeightInit init = modules::WeightInit::He) {
    return std::make_shared<modules::Conv>(context, 2, in, out, 3, modules::ConvOptions{stride, 1, true, init});
  };

  auto temb = addChild("temb", std::make_shared<Holder>());
  auto dense = temb->addChild("dense", std::make_shared<modules::ModuleList>());
  temb0_ = dense->add(std::make_shared<modules::Linear>(context, c.channels, tembChannels));
  temb1_ = dense->add(std::make_shared<modules::Linear>(context, tembChannels, tembChannels));
  convIn_ = addChild("conv_in", conv3(c.inChannels, c.channels, 1));

  std::vector<int64_t> skips{c.channels};
  int64_t channels = c.channels;
  auto down = addChild("down", std::make_shared<modules::ModuleList>());
  downBlocks_.resize(static_cast<std::size_t>(levels));
  for (int i = 0; i < levels; ++i) {
    auto level = down->add(std::make_shared<Holder>());
    auto blocks = level->addChild("block", std::make_shared<modules::ModuleList>());
    const int64_t out = c.channels * c.channelMult[static_cast<std::size_t>(i)];
    for (int j = 0; j < c.resBlocks; ++j) {
      downBlocks_[static_cast<std::size_t>(i)].push_back(blocks->add(resBlock(channels, out)));
      channels = out;
      skips.push_back(channels);
    }
    if (i < levels - 1) {
      auto sampler = level->addChild("downsample", std::make_shared<Holder>());
      downsample_.push_back(sampler->addChild("conv", conv3(channels, channels, 2)));
      skips.push_back(channels);
    }
  }

  auto mid = addChild("mid", std::make_shared<Holder>());
  mid1_ = mid->addChild("block_1", resBlock(channels, channels));
  mid2_ = mid->addChild("block_2", resBlock(channels, channels));

  // The up path runs from the deepest level, consuming skips in reverse; PyTorch lists it by level.
  struct UpLevel {
    std::vector<std::pair<int64_t, int64_t>> blocks;  // (in, out)
    int64_t channels = 0;
  };
  std::vector<UpLevel> upLevels(static_cast<std::size_t>(levels));
  for (int i = levels - 1; i >= 0; --i) {
    const int64_t out = c.channels * c.channelMult[static_cast<std::size_t>(i)];
    for (int j = 0; j <= c.resBlocks; ++j) {
      upLevels[static_cast<std::size_t>(i)].blocks.emplace_back(channels + skips.back(), out);
      skips.pop_back();
      channels = out;
    }
    upLevels[static_cast<std::size_t>(i)].channels = out;
  }
  auto up = addChild("up", std::make_shared<modules::ModuleList>());
  upBlocks_.resize(static_cast<std::size_t>(levels));
  upsample_.resize(static_cast<std::size_t>(levels));
  for (int i = 0; i < levels; ++i) {
    auto level = up->add(std::make_shared<Holder>());
    auto blocks = level->addChild("block", std::make_shared<modules::ModuleList>());
    for (const auto& [in, out] : upLevels[static_cast<std::size_t>(i)].blocks)
      upBlocks_[static_cast<std::size_t>(i)].push_back(blocks->add(resBlock(in, out)));
    if (i > 0) {
      const int64_t ch = upLevels[static_cast<std::size_t>(i)].channels;
      auto sampler = level->addChild("upsample", std::make_shared<Holder>());
      upsample_[static_cast<std::size_t>(i)] = sampler->addChild("conv", conv3(ch, ch, 1));
    }
  }
  normOut_ = addChild("norm_out", std::make_shared<modules::GroupNorm>(context, c.groups, channels, 1e-6f));
  convOut_ = addChild("conv_out", conv3(channels, c.outChannels, 1, modules::WeightInit::Zero));
}

Var DdpmUNet::forward(Tape& tape, const Var& x, const Var& t) {
  const DdpmUNetConfig& c = config_;
  const int levels = c.levels();
  if (x->value.rank() != 4 || x->value.size(1) != c.inChannels)
    throw Error("DDPM UNet: input of shape " + toString(x->value.shape()) + ", expected [N, " +
                std::to_string(c.inChannels) + ", H, W]");
  const int64_t divisor = int64_t{1} << (levels - 1);
  if (x->value.size(2) % divisor != 0 || x->value.size(3) % divisor != 0)
    throw Error("DDPM UNet: input of shape " + toString(x->value.shape()) +
                ": height and width must be divisible by " + std::to_string(divisor));
  if (t->value.numel() != x->value.size(0))
    throw Error("DDPM UNet: " + std::to_string(t->value.numel()) + " timesteps for a batch of " +
                std::to_string(x->value.size(0)));

  const Var temb = temb1_->forward(tape, fn::silu(tape, temb0_->forward(tape, fn::timestepEmbedding(tape, t, c.channels))));
  // Every block projects SiLU(temb): activated once here.
  const Var activatedTemb = fn::silu(tape, temb);
  std::vector<Var> skips;
  Var h = convIn_->forward(tape, x);
  skips.push_back(h);
  for (int i = 0; i < levels; ++i) {
    for (const auto& block : downBlocks_[static_cast<std::size_t>(i)]) {
      h = block->forwardOfActivatedEmbedding(tape, h, activatedTemb);
      skips.push_back(h);
    }
    if (i < levels - 1) {
      h = downsample_[static_cast<std::size_t>(i)]->forward(tape, h);
      skips.push_back(h);
    }
  }
  h = mid2_->forwardOfActivatedEmbedding(tape, mid1_->forwardOfActivatedEmbedding(tape, h, activatedTemb), activatedTemb);
  for (int i = levels - 1; i >= 0; --i) {
    for (const auto& block : upBlocks_[static_cast<std::size_t>(i)]) {
      h = block->forwardOfActivatedEmbedding(tape, fn::concatChannels(tape, {h, skips.back()}), activatedTemb);
      skips.pop_back();
    }
    if (i > 0)
      h = upsample_[static_cast<std::size_t>(i)]->forward(tape, fn::upsample(tape, h, 2, fn::ResampleMode::Nearest));
  }
  return convOut_->forwardOfGroupNormSilu(tape, h, *normOut_);
}

}  // namespace smokesvd::models
