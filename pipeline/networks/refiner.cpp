#include "pipeline/networks/refiner.h"

#include "nets/functional/concat.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/resample.h"
#include "runtime/error.h"

namespace smokesvd::networks {

Refiner::Refiner(Context& context, const models::UNet3PlusConfig& config) {
  if (config.dims != 2 || config.inChannels != 5 || config.outChannels != 1 || config.presenceSlots != 0)
    throw Error("NvRef: the architecture must be 2D with 5 input channels, 1 output and no presence slots");
  net_ = std::make_shared<models::UNet3Plus>(context, config);
}

RefinerOutput Refiner::forward(Tape& tape, const Var& render, const Var& minus, const Var& plus, const Var& previous,
                               const Var& beforePrevious) {
  auto blurred = [&](const Var& image) {
    return fn::upsample(tape, fn::downsample(tape, image, 2, fn::ResampleMode::Linear), 2, fn::ResampleMode::Linear);
  };
  const Var input = fn::concatChannels(tape, {render, minus, plus, blurred(previous), blurred(beforePrevious)});
  const Var residual = net_->forward(tape, input).output;
  return {fn::add(tape, render, residual), residual};
}

}  // namespace smokesvd::networks
