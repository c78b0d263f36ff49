// torch.nn.Conv2d / Conv3d (square kernels, the same stride and zero padding on every axis):
// parameters "weight" [out, in, k, k] or [out, in, k, k, k] and "bias" [out].
#pragma once

#include <vector>

#include "nets/modules/group_norm.h"
#include "nets/modules/module.h"
#include "nets/ops/conv.h"

namespace smokesvd::modules {

struct ConvOptions {
  int stride = 1;
  int padding = 0;
  bool bias = true;
  WeightInit init = WeightInit::He;
};

class Conv : public UnaryModule {
 public:
  // dims: 2 (N,C,H,W) or 3 (N,C,D,H,W).
  Conv(Context& context, int dims, int64_t inChannels, int64_t outChannels, int kernel, ConvOptions options = {});
  Var forward(Tape& tape, const Var& x) override;
  // addend + forward(x), the sum made as the output is written (a residual connection without a pass of its own).
  Var forwardPlus(Tape& tape, const Var& x, const Var& addend);
  // (addend +) forward(SiLU(norm(x))) as one op (fn::convOfGroupNormSilu): the normalised, activated input is
  // made where the convolution copies it into padded form, never as a tensor. `norm` must be affine.
  Var forwardOfGroupNormSilu(Tape& tape, const Var& x, const GroupNorm& norm, const Var& addend = nullptr);
  // forward(leakyRelu(x, negativeSlope)), plus `addend` (a Var of the output's shape; nullptr: none), with the
  // activation and the sum fused into the convolution's kernels (ops::ConvParams::inputSlope,
  // fn::conv3d's addend): no activated copy of x is made or kept and the sum has no pass of its own.
  Var forwardThroughLeakyRelu(Tape& tape, const Var& x, float negativeSlope, const Var& addend = nullptr);
  // The output channels of forward(cat(parts, 1)) in consecutive groups of outChannels each, every group
  // its own tensor (fn::convOfParts): for maps whose channels do not fit one tensor. One part and one
  // group is forward itself.
  std::vector<Var> forwardParts(Tape& tape, const std::vector<Var>& parts, const std::vector<int64_t>& outChannels);
  const Var& weight() const { return weight_; }
  const Var& bias() const { return bias_; }  // nullptr without bias

 private:
  Var convolve(Tape& tape, const Var& x, const ops::ConvParams& params, const Var& addend);
  // y, its FLOPs counted as this layer's on input x (modules::FlopCounter)
  Var counted(const Var& y, const Var& x);

  int dims_;
  ops::ConvParams params_;
  Var weight_;
  Var bias_;
};

}  // namespace smokesvd::modules
