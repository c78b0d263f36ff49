#include "pipeline/networks/side_view_synthesizer.h"

#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/functional/elementwise.h"
#include "nets/models/model_json.h"
#include "runtime/error.h"

namespace smokesvd::networks {
namespace {

Var constant(Tape& tape, float value) { return variable(Tensor::fromHost(tape.context(), {1}, std::vector<float>{value})); }

}  // namespace

DiffusionSettings diffusionSettings(const NetworkConfig& config) {
  const std::string where = config.source + " [options]";
  return {diffusion::NoiseSchedule::linear(static_cast<int>(integer(config.options, "diffusion_steps", where)),
                                           number(config.options, "beta_start", where),
                                           number(config.options, "beta_end", where)),
          config.options.contains("prediction") ? diffusion::predictionFromName(text(config.options, "prediction", where), where)
                                                : diffusion::Prediction::Noise};
}

SideViewSynthesizer::SideViewSynthesizer(Context& context, const models::DdpmUNetConfig& config, int sampleChannels,
                                         int conditionChannels, diffusion::Prediction prediction)
    : sampleChannels_(sampleChannels), conditionChannels_(conditionChannels), prediction_(prediction) {
  if (config.inChannels != sampleChannels + conditionChannels || config.outChannels != sampleChannels)
    throw Error("SvDiff: the architecture must take " + std::to_string(sampleChannels + conditionChannels) +
                " channels (" + std::to_string(sampleChannels) + " noisy, " + std::to_string(conditionChannels) +
                " condition) and predict " + std::to_string(sampleChannels));
  net_ = std::make_shared<models::DdpmUNet>(context, config);
}

std::unique_ptr<SideViewSynthesizer> makeSideViewSynthesizer(Context& context, const NetworkConfig& config) {
  if (config.network != Network::SvDiff && config.network != Network::SvDiffInit)
    throw Error(config.source + ": a side-view synthesiser needs an svdiff or svdiff-init config, not " +
                networkName(config.network));
  const bool initial = config.network == Network::SvDiffInit;
  return std::make_unique<SideViewSynthesizer>(context, models::ddpmUNetFromJson(config.model, config.source + " [model]"),
                                               initial ? 2 : 1, initial ? 2 : 5, diffusionSettings(config).prediction);
}

Var SideViewSynthesizer::predict(Tape& tape, const Var& noisy, const Var& condition, const Var& steps) {
  return net_->forward(tape, fn::concatChannels(tape, {noisy, toDiffusionRange(tape, condition)}), steps);
}

Var toDiffusionRange(Tape& tape, const Var& image) {
  return fn::broadcastBinary(tape, ops::BinaryOp::Add, fn::scale(tape, image, 2.0f), constant(tape, -1.0f));
}

Var toImageRange(Tape& tape, const Var& x) {
  return fn::scale(tape, fn::broadcastBinary(tape, ops::BinaryOp::Add, x, constant(tape, 1.0f)), 0.5f);
}

SideViewDenoiser::SideViewDenoiser(SideViewSynthesizer& synthesizer, Var condition, const diffusion::NoiseSchedule& schedule)
    : synthesizer_(synthesizer), schedule_(schedule), condition_(std::move(condition)),
      steps_(variable(Tensor(condition_->value.context(), {condition_->value.size(0)}))),
      factors_(condition_->value.context(), condition_->value.size(0)) {}

Var SideViewDenoiser::predictNoise(Tape& tape, const Var& x) {
  return diffusion::noiseFromPrediction(tape, synthesizer_.prediction(), x, synthesizer_.predict(tape, x, condition_, steps_),
                                        factors_);
}

void SideViewDenoiser::setStep(int step) {
  const auto samples = static_cast<std::size_t>(steps_->value.numel());
  steps_->value.upload(std::vector<float>(samples, static_cast<float>(step)));
  factors_.upload(diffusion::stepFactors(schedule_, std::vector<int>(samples, step)));
}

}  // namespace smokesvd::networks
