#include "nets/models/bottleneck.h"

#include <algorithm>

#include "nets/functional/activation.h"
#include "nets/functional/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::models {

Bottleneck::Bottleneck(Context& context, BottleneckOptions o) : options_(o) {
  if (o.dims != 2 && o.dims != 3) throw Error("Bottleneck: dims must be 2 or 3");
  if (o.inChannels <= 0 || o.outChannels <= 0 || o.minMid <= 0)
    throw Error("Bottleneck: channel counts must be positive");
  const int64_t mid = std::max(o.outChannels / 4, o.minMid);
  const int stride = o.downsample ? 2 : 1;
  // A fresh block is its skip connection: the branch ends in a zero-initialised convolution and the skip
  // keeps the variance (LeCun), so activations neither grow nor vanish through an unnormalised stack.
  reduce_ = addChild("reduce", std::make_shared<modules::Conv>(context, o.dims, o.inChannels, mid, 1));
  conv_ = addChild("conv", std::make_shared<modules::Conv>(context, o.dims, mid, mid, 3,
                                                           modules::ConvOptions{stride, 1}));
  expand_ = addChild("expand", std::make_shared<modules::Conv>(context, o.dims, mid, o.outChannels, 1,
                                                               modules::ConvOptions{1, 0, true, modules::WeightInit::Zero}));
  skip_ = addChild("skip", std::make_shared<modules::Conv>(
                               context, o.dims, o.inChannels, o.outChannels, o.downsample ? 2 : 1,
                               modules::ConvOptions{stride, 0, true, modules::WeightInit::Lecun}));
}

Var Bottleneck::forward(Tape& tape, const Var& x) {
  const float slope = options_.negativeSlope;
  Var h = reduce_->forwardThroughLeakyRelu(tape, x, slope);
  h = conv_->forwardThroughLeakyRelu(tape, h, slope);
  return expand_->forwardThroughLeakyRelu(tape, h, slope, skip_->forward(tape, x));
}

std::vector<Var> Bottleneck::forwardParts(Tape& tape, const std::vector<Var>& parts,
                                          const std::vector<int64_t>& outChannels) {
  int64_t total = 0;
  for (const int64_t channels : outChannels) total += channels;
  if (total != options_.outChannels)
    throw Error("Bottleneck: output groups of " + std::to_string(total) + " channels in all, the block has " +
                std::to_string(options_.outChannels));
  if (parts.size() == 1 && outChannels.size() == 1) return {forward(tape, parts[0])};
  const float slope = options_.negativeSlope;
  std::vector<Var> activated;
  for (const Var& part : parts) activated.push_back(fn::leakyRelu(tape, part, slope));
  Var h = reduce_->forwardParts(tape, activated, {reduce_->weight()->value.size(0)})[0];
  h = conv_->forward(tape, fn::leakyRelu(tape, h, slope));
  const std::vector<Var> expanded = expand_->forwardParts(tape, {fn::leakyRelu(tape, h, slope)}, outChannels);
  const std::vector<Var> skipped = skip_->forwardParts(tape, parts, outChannels);
  std::vector<Var> groups;
  for (std::size_t j = 0; j < outChannels.size(); ++j) groups.push_back(fn::add(tape, skipped[j], expanded[j]));
  return groups;
}

}  // namespace smokesvd::models
