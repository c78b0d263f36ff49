#include "pipeline/reconstruct/side_view_stage.h"

#include <algorithm>

#include "nets/functional/activation.h"
#include "nets/functional/concat.h"
#include "pipeline/media/image.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

// [0, 1] image from a diffusion sample: clamp((x + 1) / 2, 0, 1), on the host (a few thousand pixels).
std::vector<float> toImage(const std::vector<float>& sample) {
  std::vector<float> image(sample.size());
  std::transform(sample.begin(), sample.end(), image.begin(), [](float x) { return std::clamp(0.5f * (x + 1.0f), 0.0f, 1.0f); });
  return image;
}

// DDIM with the stage's options: at most `steps` steps, and no more than the start step allows.
diffusion::DdimOptions ddimOptions(const SideViewOptions& options, int steps, const diffusion::NoiseSchedule& schedule,
                                   int frame) {
  diffusion::DdimOptions ddim;
  ddim.eta = options.eta;
  ddim.seed = options.seed + static_cast<uint64_t>(frame);
  ddim.start = options.start >= schedule.steps() - 1 ? -1 : options.start;
  ddim.steps = std::min(steps, ddim.start < 0 ? schedule.steps() : ddim.start + 1);
  return ddim;
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

// A side-view sample of `shape` as [0, 1] images; with a start step, DDIM begins from the mirrored front
// views `fronts` (one image per sample channel) in the diffusion range, x = 2 w - 1.
std::vector<float> sample(Context& context, diffusion::Denoiser& denoiser, const diffusion::NoiseSchedule& schedule,
                          const Shape& shape, const diffusion::DdimOptions& ddim, const std::vector<float>& fronts) {
  if (ddim.start < 0) return toImage(diffusion::ddimSample(context, denoiser, schedule, shape, ddim).download());
  std::vector<float> start = media::mirroredRows(fronts, static_cast<int>(shape[3]));
  for (float& v : start) v = 2.0f * v - 1.0f;
  const Tensor startTensor = Tensor::fromHost(context, shape, start);
  return toImage(diffusion::ddimSample(context, denoiser, schedule, shape, ddim, &startTensor).download());
}

// The mean of options.samples samples, the k-th with its seed offset by k * 2^32.
std::vector<float> meanSample(Context& context, diffusion::Denoiser& denoiser, const diffusion::NoiseSchedule& schedule,
                              const Shape& shape, diffusion::DdimOptions ddim, const std::vector<float>& fronts,
                              int samples) {
  constexpr uint64_t kSampleSeedStride = uint64_t{1} << 32;
  std::vector<float> mean = sample(context, denoiser, schedule, shape, ddim, fronts);
  for (int k = 1; k < samples; ++k) {
    ddim.seed += kSampleSeedStride;
    const std::vector<float> next = sample(context, denoiser, schedule, shape, ddim, fronts);
    for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += next[i];
  }
  for (float& v : mean) v /= static_cast<float>(samples);
  return mean;
}

// SvDiff-init's side views of `frame` and the next one from their front views alone, [2 * h * w].
std::vector<float> initialSides(Context& context, MethodModels& models, int frame, const Tensor& front,
                                const Tensor& nextFront, const SideViewOptions& options) {
  const Shape& image = front.shape();
  const diffusion::DdimOptions ddim = ddimOptions(options, options.initSteps, models.initSchedule, frame);
  std::vector<float> fronts = front.download();
  const std::vector<float> next = nextFront.download();
  fronts.insert(fronts.end(), next.begin(), next.end());
  networks::SideViewDenoiser denoiser(*models.sideViewInit, variable(concatenated(context, {front, nextFront})),
                                      models.initSchedule);
  return meanSample(context, denoiser, models.initSchedule, {1, 2, image[2], image[3]}, ddim, fronts, options.samples);
}

}  // namespace

Tensor sideView(Context& context, MethodModels& models, FrameState& state, int frame, const Tensor& front,
                const Tensor& nextFront, const SideViewOptions& options) {
  const Shape image = front.shape();
  if (!(options.initShare >= 0.0 && options.initShare <= 1.0))
    throw Error("side view: init share " + std::to_string(options.initShare) + ", expected a value in [0, 1]");
  if (!options.synthesize) return Tensor::fromHost(context, image, media::mirroredRows(front.download(), static_cast<int>(image[3])));
  if (frame == 1) {
    Tensor side(context, image);
    Stream copy(context);
    copy.copy(state.pendingSide, side);
    copy.submit();
    return side;
  }
  if (frame == 0) {
    const std::vector<float> sides = initialSides(context, models, frame, front, nextFront, options);
    const auto half = sides.size() / 2;
    state.pendingSide.upload(std::vector<float>(sides.begin() + static_cast<std::ptrdiff_t>(half), sides.end()));
    return Tensor::fromHost(context, image, std::vector<float>(sides.begin(), sides.begin() + static_cast<std::ptrdiff_t>(half)));
  }
  std::vector<float> side;
  if (options.initShare < 1.0) {
    const diffusion::DdimOptions ddim = ddimOptions(options, options.steps, models.schedule, frame);
    networks::SideViewDenoiser denoiser(
        *models.sideView,
        variable(concatenated(context, {front, state.side1, state.sideRender1, state.side2, state.sideRender2})),
        models.schedule);
    side = meanSample(context, denoiser, models.schedule, image, ddim, front.download(), options.samples);
  }
  if (options.initShare > 0.0) {
    // The noise of frame 0's draw at every frame: consecutive estimates differ by their front views alone.
    const std::vector<float> sides = initialSides(context, models, 0, front, nextFront, options);
    const auto share = static_cast<float>(options.initShare);
    if (side.empty()) side.assign(sides.size() / 2, 0.0f);
    for (std::size_t i = 0; i < side.size(); ++i) side[i] = (1.0f - share) * side[i] + share * sides[i];
  }
  return Tensor::fromHost(context, image, side);
}

}  // namespace smokesvd::reconstruct
