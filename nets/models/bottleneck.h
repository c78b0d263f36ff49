// The pre-activation residual bottleneck blocks of the UNet3+ networks (G_rho, G_u, NvRef), 2D or 3D,
// without normalisation (docs/models.md):
//
//   Bottleneck(in, out):      y = skip(x) + expand(a(conv(a(reduce(a(x))))))
//   Bottleneck(in, out, down) the same with conv at stride 2 and skip a 2^d convolution at stride 2
//
// a = LeakyReLU(negativeSlope); reduce: 1^d conv in -> mid; conv: 3^d conv mid -> mid (padding 1);
// expand: 1^d conv mid -> out; skip: 1^d conv in -> out (2^d, stride 2 when downsampling). mid is
// max(out / 4, minMid). A fresh block is its skip: expand starts at zero and skip keeps the variance
// (LeCun-uniform), so that an unnormalised stack of blocks starts neither exploding nor vanishing. A block costs about a sixth of a conv-norm-activation pair of the same width,
// because the 3^d convolution runs at a quarter of the channels. Parameter names: reduce, conv,
// expand, skip (each .weight and .bias).
#pragma once

#include <memory>
#include <vector>

#include "nets/modules/conv.h"

namespace smokesvd::models {

struct BottleneckOptions {
  int dims = 3;               // 2 or 3
  int64_t inChannels = 0;
  int64_t outChannels = 0;
  bool downsample = false;    // halve every spatial size (sizes must be even)
  int64_t minMid = 4;         // the 3^d convolution's channels are max(out / 4, minMid)
  float negativeSlope = 0.2f;
};

class Bottleneck : public modules::UnaryModule {
 public:
  Bottleneck(Context& context, BottleneckOptions options);
  Var forward(Tape& tape, const Var& x) override;
  // forward(cat(parts, 1)) with its output in consecutive groups of outChannels each, every group its own
  // tensor and cat(parts) never formed (modules::Conv::forwardParts): for maps whose channels do not fit
  // one tensor. One part and one group is forward itself.
  std::vector<Var> forwardParts(Tape& tape, const std::vector<Var>& parts, const std::vector<int64_t>& outChannels);
  const BottleneckOptions& options() const { return options_; }

 private:
  BottleneckOptions options_;
  std::shared_ptr<modules::Conv> reduce_, conv_, expand_, skip_;
};

}  // namespace smokesvd::models
