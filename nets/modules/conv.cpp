#include "nets/modules/conv.h"

#include "nets/functional/conv.h"
#include "nets/functional/conv_of_parts.h"
#include "nets/functional/norm_silu_conv.h"
#include "nets/modules/flop_counter.h"
#include "runtime/error.h"

namespace smokesvd::modules {

Conv::Conv(Context& context, int dims, int64_t inChannels, int64_t outChannels, int kernel, ConvOptions options)
    : dims_(dims) {
  if (dims != 2 && dims != 3) throw Error("Conv: dims must be 2 or 3, got " + std::to_string(dims));
  if (kernel <= 0 || inChannels <= 0 || outChannels <= 0)
    throw Error("Conv: channels and kernel size must be positive");
  params_.stride = options.stride;
  params_.padding = options.padding;
  Shape shape{outChannels, inChannels};
  int64_t fanIn = inChannels;
  for (int axis = 0; axis < dims; ++axis) {
    shape.push_back(kernel);
    fanIn *= kernel;
  }
  weight_ = addParameter(context, "weight", shape, Init::weight(options.init, fanIn));
  if (options.bias) bias_ = addParameter(context, "bias", {outChannels}, Init::bias(options.init, fanIn));
}

Var Conv::forward(Tape& tape, const Var& x) { return convolve(tape, x, params_, nullptr); }

Var Conv::forwardPlus(Tape& tape, const Var& x, const Var& addend) { return convolve(tape, x, params_, addend); }

Var Conv::forwardOfGroupNormSilu(Tape& tape, const Var& x, const GroupNorm& norm, const Var& addend) {
  if (!norm.weight()) throw Error("Conv: a GroupNorm without affine parameters cannot be fused into its input");
  return counted(fn::convOfGroupNormSilu(tape, x, norm.weight(), norm.bias(), norm.groups(), norm.eps(), weight_,
                                         bias_, params_, addend),
                 x);
}

Var Conv::forwardThroughLeakyRelu(Tape& tape, const Var& x, float negativeSlope, const Var& addend) {
  ops::ConvParams params = params_;
  params.inputSlope = negativeSlope;
  return convolve(tape, x, params, addend);
}

Var Conv::convolve(Tape& tape, const Var& x, const ops::ConvParams& params, const Var& addend) {
  return counted(dims_ == 2 ? fn::conv2d(tape, x, weight_, bias_, params, addend)
                            : fn::conv3d(tape, x, weight_, bias_, params, addend),
                 x);
}

Var Conv::counted(const Var& y, const Var& x) {
  // weight [out, in, k...]: per output element, in * k^dims multiply-adds.
  countLayer(2.0 * static_cast<double>(y->value.numel()) * static_cast<double>(weight_->value.numel() / weight_->value.size(0)),
             y, {x}, weight_);
  return y;
}

std::vector<Var> Conv::forwardParts(Tape& tape, const std::vector<Var>& parts, const std::vector<int64_t>& outChannels) {
  if (parts.size() == 1 && outChannels.size() == 1 && outChannels[0] == weight_->value.size(0))
    return {forward(tape, parts[0])};
  int64_t total = 0;
  for (const int64_t channels : outChannels) total += channels;
  if (total != weight_->value.size(0))
    throw Error("Conv: output groups of " + std::to_string(total) + " channels in all, the weight " +
                toString(weight_->value.shape()) + " has " + std::to_string(weight_->value.size(0)));
  std::vector<Var> groups;
  int64_t begin = 0;
  for (const int64_t channels : outChannels) {
    groups.push_back(fn::convOfParts(tape, parts, weight_, bias_, params_, begin, begin + channels));
    countLayer(2.0 * static_cast<double>(groups.back()->value.numel()) *
                   static_cast<double>(weight_->value.numel() / weight_->value.size(0)),
               groups.back(), parts, weight_);
    begin += channels;
  }
  return groups;
}

}  // namespace smokesvd::modules
