// The residual block of DDPM-style UNets (2D or 3D), with optional timestep-embedding injection:
//   h = conv1(SiLU(norm1(x)))
//   h = h + temb_proj(SiLU(temb))        broadcast over positions   (when tembChannels > 0)
//   h = conv2(dropout(SiLU(norm2(h))))
//   y = shortcut(x) + h                  shortcut: identity, or nin_shortcut (1x1 conv) if channels differ
// Children and names as the reference PyTorch implementation's ResnetBlock: norm1, conv1, temb_proj,
// norm2, conv2, nin_shortcut (GroupNorm with eps 1e-6, 3x3 convolutions with padding 1), so a block's
// parameters are "norm1.weight", "norm1.bias", "conv1.weight", ..., "nin_shortcut.bias".
// Each conv(SiLU(norm(...))) runs as one op (fn::convOfGroupNormSilu: the normalised input is made where the
// convolution pads it, never as a tensor; with active dropout between them, fn::groupNormSilu then the
// convolution), and conv2 adds the shortcut as it writes its output.
#pragma once

#include <memory>

#include "nets/modules/activation.h"
#include "nets/modules/conv.h"
#include "nets/modules/group_norm.h"
#include "nets/modules/linear.h"

namespace smokesvd::modules {

struct ResBlockOptions {
  int dims = 2;               // 2 or 3
  int64_t inChannels = 0;
  int64_t outChannels = 0;    // 0: same as inChannels
  int64_t tembChannels = 0;   // 0: no timestep embedding
  int groups = 32;            // GroupNorm groups; must divide both channel counts
  float eps = 1e-6f;
  float dropout = 0.0f;
  uint64_t dropoutSeed = 0;
  WeightInit init = WeightInit::He;
};

class ResBlock : public UnaryModule {
 public:
  ResBlock(Context& context, ResBlockOptions options);
  // temb [N, tembChannels]; required when the block was built with tembChannels > 0.
  Var forward(Tape& tape, const Var& x, const Var& temb);
  // The same block given SiLU(temb) instead of temb: a network whose blocks share one embedding activates it
  // once for all of them (models::DdpmUnet).
  Var forwardOfActivatedEmbedding(Tape& tape, const Var& x, const Var& activatedTemb);
  Var forward(Tape& tape, const Var& x) override { return forward(tape, x, nullptr); }

 private:
  std::shared_ptr<GroupNorm> norm1_, norm2_;
  std::shared_ptr<Conv> conv1_, conv2_, shortcut_;
  std::shared_ptr<Linear> tembProj_;
  std::shared_ptr<Dropout> dropout_;
};

}  // namespace smokesvd::modules
