#include "pipeline/reconstruct/side_view_stage.h"

#include <algorithm>

#include "nets/functional/activation.h"
#include "nets/functional/concat.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

// [0, 1] image from a diffusion sample: clamp((x + 1) / 2, 0, 1), on the host (a few thousand pixels).
std::vector<float> toImage(const std::vector<float>& sample) {
  std::vector<float> image(sample.size());
  std::transform(sample.begin(), sample.end(), image.begin(), [](float x) { return std::clamp(0.5f * (x + 1.0f), 0.0f, 1.0f); });
  return image;
}

Tensor concatenated(Context& context, const std::vector<Tensor>& parts) {
  Stream stream(context);
  Tape tape(stream);
  NoGrad noGrad(tape);
  std::vector<Var> vars;
  for (const Tensor& t : parts) vars.push_back(variable(t));
  const Var out = fn::concatChannels(tape, vars);
  stream.submit();
  return out->value;
}

}  // namespace

Tensor sideView(Context& context, MethodModels& models, FrameState& state, int frame, const Tensor& front,
                const Tensor& nextFront, const SideViewOptions& options) {
  const Shape image = front.shape();
  if (!options.synthesize) {
    std::vector<float> mirrored = front.download();
    const auto width = static_cast<std::size_t>(image[3]);
    for (std::size_t row = 0; row < mirrored.size(); row += width)
      std::reverse(mirrored.begin() + static_cast<std::ptrdiff_t>(row), mirrored.begin() + static_cast<std::ptrdiff_t>(row + width));
    return Tensor::fromHost(context, image, mirrored);
  }
  if (frame == 1) {
    Tensor side(context, image);
    Stream copy(context);
    copy.copy(state.pendingSide, side);
    copy.submit();
    return side;
  }
  diffusion::DdimOptions ddim;
  ddim.eta = options.eta;
  ddim.seed = options.seed + static_cast<uint64_t>(frame);
  if (frame == 0) {
    ddim.steps = std::min(options.initSteps, models.initSchedule.steps());
    networks::SideViewDenoiser denoiser(*models.sideViewInit, variable(concatenated(context, {front, nextFront})));
    const std::vector<float> both = toImage(
        diffusion::ddimSample(context, denoiser, models.initSchedule, {1, 2, image[2], image[3]}, ddim).download());
    const auto half = both.size() / 2;
    state.pendingSide.upload(std::vector<float>(both.begin() + static_cast<std::ptrdiff_t>(half), both.end()));
    return Tensor::fromHost(context, image, std::vector<float>(both.begin(), both.begin() + static_cast<std::ptrdiff_t>(half)));
  }
  ddim.steps = std::min(options.steps, models.schedule.steps());
  networks::SideViewDenoiser denoiser(
      *models.sideView, variable(concatenated(context, {front, state.side1, state.sideRender1, state.side2, state.sideRender2})));
  return Tensor::fromHost(context, image, toImage(diffusion::ddimSample(context, denoiser, models.schedule, image, ddim).download()));
}

}  // namespace smokesvd::reconstruct
