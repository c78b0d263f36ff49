// SvDiff and SvDiff-init as the pipeline uses them: conditional DDPM UNets predicting the noise of side
// views. Images live in [0, 1] everywhere else in the pipeline; the diffusion runs in [-1, 1] (x = 2 w - 1),
// the condition too:
//   out = UNet(cat(x_t, 2 c - 1), t)
// out is the noise eps (epsilon prediction, the paper's) or v = sqrt(abar) eps - sqrt(1 - abar) x_0 (v
// prediction), as the config's options.prediction says (nets/diffusion/prediction.h).
// SvDiff: x_t [N, 1, h, w] the side view of frame t; condition [N, 5, h, w] = (front view w_t, the
// synthesised side view of t-1 and the side render of the density reconstructed from it, the same for t-2).
// SvDiff-init: x_t [N, 2, h, w] the side views of frames 0 and 1; condition [N, 2, h, w] their front views.
#pragma once

#include <memory>

#include "nets/diffusion/ddim.h"
#include "nets/diffusion/forward_process.h"
#include "nets/diffusion/prediction.h"
#include "nets/diffusion/schedule.h"
#include "nets/models/ddpm_unet.h"
#include "pipeline/networks/network_config.h"

namespace smokesvd::networks {

// The diffusion of an SvDiff or SvDiff-init config's options: the linear schedule (diffusion_steps,
// beta_start, beta_end) and what the network predicts (prediction: "epsilon", the default, or "v").
struct DiffusionSettings {
  diffusion::NoiseSchedule schedule;
  diffusion::Prediction prediction;
};
DiffusionSettings diffusionSettings(const NetworkConfig& config);

class SideViewSynthesizer {
 public:
  // sampleChannels 1 (SvDiff) or 2 (SvDiff-init); conditionChannels 5 or 2.
  SideViewSynthesizer(Context& context, const models::DdpmUNetConfig& config, int sampleChannels, int conditionChannels,
                      diffusion::Prediction prediction = diffusion::Prediction::Noise);
  // The network's output (eps or v): noisy [N, S, h, w] in [-1, 1]; condition [N, C, h, w] in [0, 1]; steps [N].
  Var predict(Tape& tape, const Var& noisy, const Var& condition, const Var& steps);
  diffusion::Prediction prediction() const { return prediction_; }
  models::DdpmUNet& net() { return *net_; }
  int sampleChannels() const { return sampleChannels_; }
  int conditionChannels() const { return conditionChannels_; }

 private:
  std::shared_ptr<models::DdpmUNet> net_;
  int sampleChannels_, conditionChannels_;
  diffusion::Prediction prediction_;
};

// The synthesiser a trained SvDiff or SvDiff-init config describes (architecture, channels, prediction),
// weights not loaded. Throws Error for a config of another network.
std::unique_ptr<SideViewSynthesizer> makeSideViewSynthesizer(Context& context, const NetworkConfig& config);

// [0, 1] images to the diffusion range and back: x = 2 w - 1, w = (x + 1) / 2.
Var toDiffusionRange(Tape& tape, const Var& image);
Var toImageRange(Tape& tape, const Var& x);

// The synthesiser as a DDIM denoiser for one condition (uploaded by the caller into `condition`): its
// output turned into the noise it implies at the step set last (identity for epsilon prediction).
class SideViewDenoiser : public diffusion::Denoiser {
 public:
  SideViewDenoiser(SideViewSynthesizer& synthesizer, Var condition, const diffusion::NoiseSchedule& schedule);
  Var predictNoise(Tape& tape, const Var& x) override;
  void setStep(int step) override;

 private:
  SideViewSynthesizer& synthesizer_;
  const diffusion::NoiseSchedule& schedule_;
  Var condition_, steps_;
  diffusion::StepFactorTensors factors_;
};

}  // namespace smokesvd::networks
