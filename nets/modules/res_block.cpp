#include "nets/modules/res_block.h"

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "runtime/error.h"

namespace smokesvd::modules {

ResBlock::ResBlock(Context& context, ResBlockOptions o) {
  const int64_t out = o.outChannels > 0 ? o.outChannels : o.inChannels;
  if (o.inChannels <= 0) throw Error("ResBlock: inChannels must be positive");
  const ConvOptions conv3{1, 1, true, o.init};
  norm1_ = addChild("norm1", std::make_shared<GroupNorm>(context, o.groups, o.inChannels, o.eps));
  conv1_ = addChild("conv1", std::make_shared<Conv>(context, o.dims, o.inChannels, out, 3, conv3));
  if (o.tembChannels > 0)
    tembProj_ = addChild("temb_proj", std::make_shared<Linear>(context, o.tembChannels, out, true, o.init));
  norm2_ = addChild("norm2", std::make_shared<GroupNorm>(context, o.groups, out, o.eps));
  dropout_ = addChild("dropout", std::make_shared<Dropout>(o.dropout, o.dropoutSeed));
  conv2_ = addChild("conv2", std::make_shared<Conv>(context, o.dims, out, out, 3, conv3));
  if (out != o.inChannels)
    shortcut_ = addChild("nin_shortcut",
                         std::make_shared<Conv>(context, o.dims, o.inChannels, out, 1, ConvOptions{1, 0, true, o.init}));
}

Var ResBlock::forward(Tape& tape, const Var& x, const Var& temb) {
  return forwardOfActivatedEmbedding(tape, x, temb ? fn::silu(tape, temb) : nullptr);
}

Var ResBlock::forwardOfActivatedEmbedding(Tape& tape, const Var& x, const Var& activatedTemb) {
  if (tembProj_ && !activatedTemb) throw Error("ResBlock: built with a timestep embedding, called without one");
  if (!tembProj_ && activatedTemb) throw Error("ResBlock: called with a timestep embedding it was not built for");
  Var h = conv1_->forwardOfGroupNormSilu(tape, x, *norm1_);
  if (tembProj_) h = fn::addChannel(tape, h, tembProj_->forward(tape, activatedTemb));
  const Var shortcut = shortcut_ ? shortcut_->forward(tape, x) : x;
  if (dropout_->passesThrough()) return conv2_->forwardOfGroupNormSilu(tape, h, *norm2_, shortcut);
  return conv2_->forwardPlus(tape, dropout_->forward(tape, norm2_->forwardThenSilu(tape, h)), shortcut);
}

}  // namespace smokesvd::modules
