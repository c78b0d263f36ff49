// The attention-free conditional DDPM UNet of SvDiff (epsilon prediction), 2D. The condition is
// concatenated to the noisy image on channels by the caller: x = cat(x_t, condition). Layout
// (Ho et al. 2020 without attention; names as the PyTorch DDPM port, so weights move unchanged):
//
//   temb = temb.dense.1(SiLU(temb.dense.0(sinusoid(t, ch))))          ch -> 4 ch -> 4 ch
//   h = conv_in(x)                                                     3x3, in -> ch
//   level i = 0..L-1 (channels ch * mult[i]):
//     resBlocks x  h = down.i.block.j(h, temb)      each output kept as a skip
//     i < L-1:     h = down.i.downsample.conv(h)   3x3 stride 2, padding 1 (kept as a skip too)
//   h = mid.block_2(mid.block_1(h, temb), temb)
//   level i = L-1..0:
//     resBlocks + 1 x  h = up.i.block.j(cat(h, last skip), temb)
//     i > 0:           h = up.i.upsample.conv(nearest_x2(h))           3x3, padding 1
//   eps = conv_out(SiLU(norm_out(h)))                                  3x3 -> out, zero-initialised
//
// The blocks are modules::ResBlock (GroupNorm, SiLU, timestep embedding added per channel after the
// first conv). Every spatial size must be divisible by 2^(L-1).
#pragma once

#include <memory>
#include <vector>

#include "nets/modules/conv.h"
#include "nets/modules/group_norm.h"
#include "nets/modules/linear.h"
#include "nets/modules/res_block.h"

namespace smokesvd::models {

struct DdpmUNetConfig {
  int64_t inChannels = 1;    // noisy image channels + condition channels
  int64_t outChannels = 1;   // predicted noise channels
  int64_t channels = 32;     // ch
  std::vector<int64_t> channelMult{1, 2, 2, 2};
  int resBlocks = 2;
  int groups = 8;            // GroupNorm groups; must divide every level's channels
  float dropout = 0.0f;

  int levels() const { return static_cast<int>(channelMult.size()); }
  void validate() const;  // Error naming the field
};

class DdpmUNet : public modules::Module {
 public:
  DdpmUNet(Context& context, DdpmUNetConfig config);
  // x [N, in, H, W]; t [N] diffusion steps (integers stored as floats). Returns eps [N, out, H, W].
  Var forward(Tape& tape, const Var& x, const Var& t);
  const DdpmUNetConfig& config() const { return config_; }

 private:
  DdpmUNetConfig config_;
  std::shared_ptr<modules::Linear> temb0_, temb1_;
  std::shared_ptr<modules::Conv> convIn_, convOut_;
  std::vector<std::vector<std::shared_ptr<modules::ResBlock>>> downBlocks_, upBlocks_;  // [level][j]
  std::vector<std::shared_ptr<modules::Conv>> downsample_, upsample_;                   // [level]
  std::shared_ptr<modules::ResBlock> mid1_, mid2_;
  std::shared_ptr<modules::GroupNorm> normOut_;
};

}  // namespace smokesvd::models
