#include "nets/diffusion/ddim.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "nets/diffusion/gaussian.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::diffusion {

void DdimOptions::validate(const NoiseSchedule& schedule) const {
  if (start < -1 || start >= schedule.steps())
    throw Error("DDIM: the start step must be -1 (from pure noise) or in [0, " + std::to_string(schedule.steps() - 1) +
                "], got " + std::to_string(start));
  const int highest = start < 0 ? schedule.steps() : start + 1;
  if (steps < 1 || steps > highest)
    throw Error("DDIM: steps must be in [1, " + std::to_string(highest) + "]" +
                (start < 0 ? "" : " for start step " + std::to_string(start)) + ", got " + std::to_string(steps));
  if (!(eta >= 0.0 && std::isfinite(eta))) throw Error("DDIM: eta must be a finite number >= 0");
  if (clipClean && !(clipMin < clipMax)) throw Error("DDIM: the clip range must have min < max");
}

std::vector<int> ddimSteps(int trainSteps, int samplingSteps, int start) {
  const int span = start < 0 ? trainSteps : std::min(start + 1, trainSteps);
  if (samplingSteps < 1 || samplingSteps > span)
    throw Error("DDIM: sampling steps must be in [1, " + std::to_string(span) + "]");
  if (samplingSteps == 1) return {span - 1};
  const int stride = span / samplingSteps;
  std::vector<int> steps;
  for (int i = 0; i < samplingSteps; ++i) steps.push_back(i * stride);
  return steps;
}

std::vector<float> ddimCoefficients(const NoiseSchedule& schedule, int step, int nextStep, const DdimOptions& options) {
  if (nextStep >= step) throw Error("DDIM: the next step must be lower than the current one");
  const double abar = schedule.alphaBar(step), abarNext = schedule.alphaBar(nextStep);
  const double sigma = options.eta * std::sqrt((1.0 - abarNext) / (1.0 - abar)) * std::sqrt(1.0 - abar / abarNext);
  const double direction = std::sqrt(std::max(0.0, 1.0 - abarNext - sigma * sigma));
  return {static_cast<float>(std::sqrt(abar)), static_cast<float>(std::sqrt(1.0 - abar)),
          static_cast<float>(std::sqrt(abarNext)), static_cast<float>(direction), static_cast<float>(sigma),
          options.clipClean ? 1.0f : 0.0f, options.clipMin, options.clipMax};
}

void recordDdimStep(Stream& stream, const Tensor& x, const Tensor& eps, const Tensor& z, const Tensor& coefficients,
                    const Tensor& next, const Tensor& clean) {
  for (const Tensor* t : {&eps, &z, &next, &clean})
    if (t->shape() != x.shape())
      throw Error("DDIM step: every tensor must have the state's shape " + toString(x.shape()) + ", got " +
                  toString(t->shape()));
  if (coefficients.numel() != 8) throw Error("DDIM step: expected 8 coefficients, got " + toString(coefficients.shape()));
  const auto n = static_cast<uint32_t>(x.numel());
  stream.dispatchFlat(stream.kernel("nn/ddim_step", {128, 1, 1}),
                      {asVec4(x), asVec4(eps), asVec4(z), coefficients, next, clean}, n, (n + 3) / 4);
}

Tensor ddimSample(Context& context, Denoiser& denoiser, const NoiseSchedule& schedule, const Shape& shape,
                  const DdimOptions& options, const Tensor* start) {
  options.validate(schedule);
  if (options.start >= 0 && options.start < schedule.steps() - 1 && !start)
    throw Error("DDIM: a start step below " + std::to_string(schedule.steps() - 1) + " needs a start image");
  if (start && start->shape() != shape)
    throw Error("DDIM: the start image has shape " + toString(start->shape()) + ", the sample " + toString(shape));
  const std::vector<int> steps = ddimSteps(schedule.steps(), options.steps, options.start);
  Gaussian gaussian(options.seed);
  std::vector<float> initial = gaussian.values(static_cast<std::size_t>(numElements(shape)));
  if (start) {
    const double abar = schedule.alphaBar(steps.back());
    const std::vector<float> image = start->download();
    for (std::size_t i = 0; i < initial.size(); ++i)
      initial[i] = static_cast<float>(std::sqrt(abar) * image[i] + std::sqrt(1.0 - abar) * initial[i]);
  }
  const Tensor x = Tensor::fromHost(context, shape, initial);
  const Tensor z(context, shape), next(context, shape), clean(context, shape), coefficients(context, {8});
  z.upload(std::vector<float>(static_cast<std::size_t>(z.numel()), 0.0f));

  Stream stream(context);
  Tape tape(stream);
  {
    NoGrad noGrad(tape);
    const Var eps = denoiser.predictNoise(tape, variable(x));
    if (eps->value.shape() != shape)
      throw Error("DDIM: the denoiser predicted noise of shape " + toString(eps->value.shape()) + " for a sample of " +
                  toString(shape));
    recordDdimStep(stream, x, eps->value, z, coefficients, next, clean);
    stream.copy(next, x);
  }

  for (std::size_t i = steps.size(); i-- > 0;) {
    const int t = steps[i];
    const int tNext = i == 0 ? -1 : steps[i - 1];
    const std::vector<float> c = ddimCoefficients(schedule, t, tNext, options);
    coefficients.upload(c);
    if (c[4] > 0) z.upload(gaussian.values(static_cast<std::size_t>(z.numel())));
    denoiser.setStep(t);
    stream.submit();
  }
  return x;
}

}  // namespace smokesvd::diffusion
