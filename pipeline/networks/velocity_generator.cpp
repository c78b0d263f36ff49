#include "pipeline/networks/velocity_generator.h"

#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "runtime/error.h"

namespace smokesvd::networks {

VelocityGenerator::VelocityGenerator(Context& context, const models::UNet3PlusConfig& config, const Preset& preset)
    : grid_(preset.grid) {
  if (config.dims != 3 || config.inChannels != 2 || config.outChannels != 3 || config.presenceSlots != 0)
    throw Error("G_u: the architecture must be 3D with 2 input channels, 3 outputs and no presence slots");
  net_ = std::make_shared<models::UNet3Plus>(context, config);
}

VelocityOutput VelocityGenerator::forward(Tape& tape, const Var& current, const Var& next, bool deepSupervision) {
  const Shape one{1, 1, grid_.z, grid_.y, grid_.x}, field = grid_.vector();
  const Var input = fn::concatChannels(tape, {fn::reshape(tape, current, one), fn::reshape(tape, next, one)});
  const models::UNet3PlusOutput out = net_->forward(tape, input, nullptr, deepSupervision);
  VelocityOutput result{fn::reshape(tape, out.output, field), {}};
  for (const Var& head : out.supervision) result.supervision.push_back(fn::reshape(tape, head, field));
  return result;
}

}  // namespace smokesvd::networks
