// Training SvDiff and SvDiff-init (paper Sec. 3.2, Algorithm 1). Side and front views are rendered in
// the step from the simulated densities with the sample's look. A step draws one diffusion step s; with
// probability TQ / T it is a guided step (s < TQ), otherwise s >= TQ, so s stays uniform on [0, T).
//
// L_noise is the MSE of the network's output to its target: the noise eps (options.prediction "epsilon",
// the paper's) or v = sqrt(abar) eps - sqrt(1 - abar) x0 ("v"; nets/diffusion/prediction.h); x0^ below is
// the clean estimate that output implies.
//
// SvDiff (frames t >= 2): an unguided step trains one frame, L_noise = ||eps - eps^||^2, conditioned on
// the true side views of t-1 and t-2 and the side renders of the coarse G_rho's densities of them. A
// guided step runs options.frames frames t .. t+F-1 (the multi-frame scheme): each frame's clean estimate
// x0^ (eq. 3) becomes the synthesised side view that, with the side render of the coarse G_rho's density
// from (front, x0^), conditions the next frame, and the guidance losses join:
//   L_img = ||x0 - x0^||^2,  L_sp = ||H(x0^) - H(w_front)||^2,
//   L_vel = mean (div u)^2 + mean |grad u|^2, u = G_u(rho_prev, G_rho(front, x0^)),
// each averaged over the frames, gradients flowing through the frozen G_rho and G_u and along the chain.
// options.multi_frame = false conditions every frame on the true side views instead (the ablation);
// options.guidance = false drops the guidance losses (and with them the guided steps).
// options.multi_frame_steps = "all" (beyond the paper; default "guided") runs the F-frame chain on unguided
// steps too (s >= TQ, L_noise only): there x0^ is far from the truth (at s near T the model's guess from the
// condition alone), so the later frames learn from conditions as wrong as their own earlier outputs.
// options.init_history = p (beyond the paper; default 0): with probability p a sample's history, the side
// views of t-2 and t-1, is SvDiff-init's estimate of them from their front views instead of the truth (its
// clean estimate at step T - 1 from pure noise, clamped to [0, 1]: a one-step DDIM sample, what an
// autoregressive rollout starts from), with the side renders of the coarse densities from (front, estimate).
// The model then learns to correct an inference-like history from the front view instead of copying it.
// Needs options.init_model "svdiff-init" (frozen, from the models folder); those samples are their own
// variants ("...-init-history").
//
// SvDiff-init (frame pairs t, t+1): x = the two side views, the condition their two front views;
// L_noise, and on guided steps L_img and L_sp.
//
// Validation on held-out frames, one frame (SvDiff-init: one pair) conditioned on the truth, at steps 25, 100,
// 400, 800 and T - 1: the PSNR of the clean estimate against the true side view (at T - 1 the noisy input
// holds almost nothing of it: the estimate is the model's guess from the condition alone) and the MSE of the
// noise the prediction implies.
#pragma once

#include <memory>
#include <utility>

#include "nets/diffusion/forward_process.h"
#include "nets/diffusion/schedule.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/networks/side_view_synthesizer.h"
#include "pipeline/networks/velocity_generator.h"
#include "pipeline/render/view_set.h"
#include "pipeline/train/look_slot.h"
#include "pipeline/train/sample_draw.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

class SvDiffTrainer : public StageTrainer {
 public:
  // initial: SvDiff-init, else SvDiff.
  SvDiffTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
                const std::filesystem::path& models, bool initial);

  modules::Module& model() override { return synthesizer_.net(); }
  std::vector<std::string> variants() const override;
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double noise, image, rowSum, velocity;
  };
  struct FrontSide {
    Var front, side;  // [1, 1, h, w] each
  };
  // Uploads the densities of `frames` frames from `first` (SvDiff) or pairs (SvDiff-init), the noise and step.
  int upload(const dataset::SceneEntry& scene, const std::vector<int>& frames, const Augmentation& a, int step,
             diffusion::Gaussian& random);
  // The first frame's errors (validation): MSE of the noise the prediction implies and of the clean estimate.
  struct FrameErrors {
    Var noise, clean;
  };
  FrameErrors frameErrors(Tape& tape, const Var& clean, const Var& noise, const Var& noisy, const Var& predicted);
  FrontSide frontSide(Tape& tape, const Var& density, const render::RenderSettings& settings);
  LossTerms recordInitial(Tape& tape, bool guided, const render::RenderSettings& settings, FrameErrors* errors = nullptr);
  LossTerms recordSequence(Tape& tape, bool guided, bool initHistory, const render::RenderSettings& settings,
                           FrameErrors* errors = nullptr);
  // SvDiff-init's one-step estimates of the side views of densities 0 and 1 from their front views, [0, 1].
  std::pair<Var, Var> initEstimates(Tape& tape, const Var& front0, const Var& front1);
  int framesPerSample() const;

  Context& context_;
  networks::NetworkConfig config_;
  const dataset::SceneDataset& data_;
  bool initial_;
  Weights weights_{};
  int frames_ = 4;
  bool multiFrame_ = true, guidance_ = true;
  bool multiFrameEveryStep_ = false;  // options.multi_frame_steps == "all"
  int threshold_ = 200;
  int batch_ = 1;
  diffusion::NoiseSchedule schedule_;
  networks::SideViewSynthesizer synthesizer_;
  std::unique_ptr<networks::DensityGenerator> coarse_;
  std::unique_ptr<networks::VelocityGenerator> velocity_;
  double initHistory_ = 0;                                  // options.init_history
  std::unique_ptr<networks::SideViewSynthesizer> init_;     // frozen SvDiff-init, when initHistory_ > 0
  Var initNoise_, initSteps_;                               // [1, 2, h, w] pure noise; [1] = T - 1
  std::unique_ptr<diffusion::StepFactorTensors> initFactors_;
  render::ViewSet frontSideViews_, sideView_;
  LookSlot look_;
  std::vector<Var> densities_;  // per sample, per frame
  std::vector<Var> noise_;      // SvDiff: per frame [1, 1, h, w]; SvDiff-init: one [B, 2, h, w]
  Var steps_;
  diffusion::StepFactorTensors factors_;
};

}  // namespace smokesvd::train
