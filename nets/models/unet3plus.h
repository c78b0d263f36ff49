// UNet3+ (Huang et al. 2020) with full-scale skip aggregation, 2D or 3D, built from the residual
// bottleneck blocks of nets/models/bottleneck.h: the architecture of G_rho (density from lifted views),
// G_u (velocity from two densities) and NvRef (a residual for a blurry render). docs/models.md has the
// layer-by-layer description; this is its outline, with L levels of filters f_0..f_{L-1} and c
// channels per decoder source:
//
//   x_0 = stem(x)                              3^d conv in -> f_0, padding 1 (+ presence(p), below)
//   x_l = Bottleneck(f_{l-1} -> f_l, down)(x_{l-1})           l = 1..L-1 (each halves every size)
//   decoder stage d = L-2 .. 0 (resolution of level d) fuses one source per level s = 0..L-1:
//     s < d           Bottleneck(f_s -> c)(maxpool^(d-s) x_s)       pooled first, block at level d
//     s = d           Bottleneck(f_d -> c)(x_d)
//     d < s < L-1     upsample_2^(s-d)(Bottleneck(L c -> c)(hd_s))  block at level s, then trilinear
//     s = L-1         upsample_2^(L-1-d)(Bottleneck(f_{L-1} -> c)(x_{L-1}))
//     hd_d = Bottleneck(L c -> L c)(cat(sources, level order))
//   y = output(head_0(hd_0))                   head_k: 1^d conv -> out; output: identity or ReLU
//   deep supervision: output(head_k(hd_k)) for k = 1..L-2 and output(head_{L-1}(x_{L-1})), each
//   nearest-upsampled to full size
//
// Every block runs at the coarser of its source's and its target's resolution ("lean" UNet3+), which
// halves the cost of the canonical layout (where deeper maps are upsampled before their block).
// Every spatial size must be divisible by 2^(L-1).
//
// Large maps: a fused map hd_d whose L c channels would not fit one tensor (the device's
// DeviceInfo::maxTensorBytes: the paper preset's hd_0, 160 channels at 64 x 112 x 64, is 280 MiB and
// lavapipe's limit 128 MiB) is kept as its L source-sized channel parts: its fusion block, the blocks that
// read it and its head run on the parts (Bottleneck::forwardParts), and cat(sources) is never formed. The
// products are the same; sums over channels are accumulated part by part, so outputs differ from the
// one-tensor path by rounding only. Parameters and their names do not change.
//
// presence: with presenceSlots > 0, forward takes p [N, slots] (1 where a view slot holds an image,
// 0 where it is missing) and adds Linear(slots -> f_0)(p) to every voxel of the stem's output. That is
// exactly what constant per-slot presence channels contribute through the stem's convolution away from
// the border, without their cost: "no view" differs from "a view of nothing".
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "nets/models/bottleneck.h"
#include "nets/modules/linear.h"

namespace smokesvd::models {

enum class OutputActivation { None, ReLU };

struct UNet3PlusConfig {
  int dims = 3;
  int64_t inChannels = 1;
  int64_t outChannels = 1;
  std::vector<int64_t> filters{8, 16, 32, 64};  // per level, L = filters.size() >= 2
  int64_t catChannels = 8;                      // c: channels each decoder source contributes
  int64_t minMid = 4;                           // bottleneck width floor (bottleneck.h)
  float negativeSlope = 0.2f;
  OutputActivation output = OutputActivation::None;
  int64_t presenceSlots = 0;                    // > 0: forward takes a presence vector [N, slots]

  int levels() const { return static_cast<int>(filters.size()); }
  void validate() const;  // Error naming the field
};

struct UNet3PlusOutput {
  Var output;                   // [N, out, spatial...]
  std::vector<Var> supervision; // deep-supervision heads 1..L-1 at full size (empty unless asked for)
};

class UNet3Plus : public modules::Module {
 public:
  UNet3Plus(Context& context, UNet3PlusConfig config);

  // x [N, in, spatial...]; presence [N, slots] when the config has presence slots, else nullptr.
  UNet3PlusOutput forward(Tape& tape, const Var& x, const Var& presence = nullptr, bool deepSupervision = false);
  const UNet3PlusConfig& config() const { return config_; }
  // Fused maps above this many bytes are kept in channel parts (above); the device's largest tensor
  // unless set (tests set it to take the parts path at small sizes).
  void setLargestTensorBytes(uint64_t bytes) { largestTensorBytes_ = bytes; }

 private:
  using Parts = std::vector<Var>;  // one map as channel parts, in channel order (usually one part)
  Var source(Tape& tape, int stage, int level, const std::vector<Var>& encoder, const std::vector<Parts>& decoder);

  UNet3PlusConfig config_;
  uint64_t largestTensorBytes_;
  std::shared_ptr<modules::Conv> stem_;
  std::shared_ptr<modules::Linear> presence_;
  std::vector<std::shared_ptr<Bottleneck>> down_;                  // down_[l - 1] makes x_l
  std::vector<std::vector<std::shared_ptr<Bottleneck>>> sources_;  // [stage][level]
  std::vector<std::shared_ptr<Bottleneck>> fuse_;                  // [stage]
  std::vector<std::shared_ptr<modules::Conv>> heads_;              // [level]
};

}  // namespace smokesvd::models
