#include "pipeline/networks/density_generator.h"

#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/models/model_json.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/trained_model.h"
#include "pipeline/networks/view_slots.h"
#include "runtime/error.h"

namespace smokesvd::networks {

DensityGenerator::DensityGenerator(Context& context, const models::UNet3PlusConfig& config, const Preset& preset)
    : preset_(preset), grid_(presetGrid(preset)) {
  if (config.dims != 3 || config.inChannels != kSlots || config.outChannels != 1 || config.presenceSlots != kSlots)
    throw Error("G_rho: the architecture must be 3D with 16 input channels, 1 output and 16 presence slots");
  net_ = std::make_shared<models::UNet3Plus>(context, config);
  const std::vector<Camera> cameras = slotCameras(preset);
  views_ = render::uploadViews(context, cameras);
}

Var DensityGenerator::slotImages(Tape& tape, const std::vector<std::pair<int, Var>>& images) const {
  const Shape one{1, 1, views_.height, views_.width};
  const Var zero = variable(Tensor::fromHost(tape.context(), one, std::vector<float>(static_cast<std::size_t>(views_.height * views_.width), 0.0f)));
  std::vector<Var> slots(kSlots, zero);
  for (const auto& [slot, image] : images) {
    if (slot < 0 || slot >= kSlots) throw Error("G_rho: view slot " + std::to_string(slot) + " outside [0, 16)");
    slots[static_cast<std::size_t>(slot)] = fn::reshape(tape, image, one);
  }
  return fn::reshape(tape, fn::concatChannels(tape, slots), {kSlots, 1, views_.height, views_.width});
}

DensityOutput DensityGenerator::forward(Tape& tape, const Var& images, const Var& presence, bool deepSupervision) {
  const Shape volume = grid_.volume();
  const models::UNet3PlusOutput out =
      net_->forward(tape, diff::lift(tape, images, views_, grid_), fn::reshape(tape, presence, {1, kSlots}), deepSupervision);
  DensityOutput result{fn::reshape(tape, out.output, volume), {}};
  for (const Var& head : out.supervision) result.supervision.push_back(fn::reshape(tape, head, volume));
  return result;
}

std::unique_ptr<DensityGenerator> loadFrozenDensityGenerator(Context& context, const std::filesystem::path& models,
                                                             Network network, const Preset& preset) {
  const TrainedModel trained = findTrainedModel(models, network, preset);
  auto generator = std::make_unique<DensityGenerator>(
      context, models::unet3PlusFromJson(trained.config.model, trained.config.source + " [model]"), preset);
  loadTrainedWeights(trained, generator->net());
  freeze(generator->net());
  return generator;
}

}  // namespace smokesvd::networks
