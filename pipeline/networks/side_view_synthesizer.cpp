#include "pipeline/networks/side_view_synthesizer.h"

#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/functional/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::networks {
namespace {

Var constant(Tape& tape, float value) { return variable(Tensor::fromHost(tape.context(), {1}, std::vector<float>{value})); }

}  // namespace

SideViewSynthesizer::SideViewSynthesizer(Context& context, const models::DdpmUNetConfig& config, int sampleChannels,
                                         int conditionChannels)
    : sampleChannels_(sampleChannels), conditionChannels_(conditionChannels) {
  if (config.inChannels != sampleChannels + conditionChannels || config.outChannels != sampleChannels)
    throw Error("SvDiff: the architecture must take " + std::to_string(sampleChannels + conditionChannels) +
                " channels (" + std::to_string(sampleChannels) + " noisy, " + std::to_string(conditionChannels) +
                " condition) and predict " + std::to_string(sampleChannels));
  net_ = std::make_shared<models::DdpmUNet>(context, config);
}

Var SideViewSynthesizer::predictNoise(Tape& tape, const Var& noisy, const Var& condition, const Var& steps) {
  return net_->forward(tape, fn::concatChannels(tape, {noisy, toDiffusionRange(tape, condition)}), steps);
}

Var toDiffusionRange(Tape& tape, const Var& image) {
  return fn::broadcastBinary(tape, ops::BinaryOp::Add, fn::scale(tape, image, 2.0f), constant(tape, -1.0f));
}

Var toImageRange(Tape& tape, const Var& x) {
  return fn::scale(tape, fn::broadcastBinary(tape, ops::BinaryOp::Add, x, constant(tape, 1.0f)), 0.5f);
}

SideViewDenoiser::SideViewDenoiser(SideViewSynthesizer& synthesizer, Var condition)
    : synthesizer_(synthesizer), condition_(std::move(condition)),
      steps_(variable(Tensor(condition_->value.context(), {condition_->value.size(0)}))) {}

Var SideViewDenoiser::predictNoise(Tape& tape, const Var& x) { return synthesizer_.predictNoise(tape, x, condition_, steps_); }

void SideViewDenoiser::setStep(int step) {
  steps_->value.upload(std::vector<float>(static_cast<std::size_t>(steps_->value.numel()), static_cast<float>(step)));
}

}  // namespace smokesvd::networks
