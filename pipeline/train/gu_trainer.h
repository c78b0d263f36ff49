// Training G_u (supplement C.5): u = G_u(rho_t, rho_t+1), centred, against the simulated velocity u*
// (MAC, averaged to the cell centres):
//   L = l_u ||u - u*||^2 + l_div ||div u - div u*||^2 + l_ds sum_k ||u_k - u*||^2 / K
//     + l_adv ||A(rho_t, u) + inflow_t+1 - rho_t+1||^2 + l_R mean_a ||R(A(rho_t, u) + inflow_t+1, a) - R(rho_t+1, a)||^2
// A is the differentiable MacCormack advection of the scene's flags (u turned into MAC), R the renderer
// at options.render_views orbit views with the sample's look. Its last options.finetune_steps steps
// (paper D, the second stage) take the inputs from the fine G_rho, given the true renders of all 16
// views, so that G_u learns the densities it will see; the targets stay the simulated fields.
// Validation (true densities in): the velocity RMSE, and the error of the advected density against the
// next frame divided by the error of assuming no motion (rho_t + inflow_t+1).
#pragma once

#include <memory>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/networks/velocity_generator.h"
#include "pipeline/physics/grid.h"
#include "pipeline/render/view_set.h"
#include "pipeline/train/look_slot.h"
#include "pipeline/train/sample_draw.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

class GuTrainer : public StageTrainer {
 public:
  GuTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
            const std::filesystem::path& models);

  modules::Module& model() override { return generator_.net(); }
  std::vector<std::string> variants() const override { return {"truth-unlit", "truth-lit", "grho-unlit", "grho-lit"}; }
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double velocity, divergence, deepSupervision, advectedDensity, advectedRender;
  };
  int upload(const dataset::SceneEntry& scene, int frame, const Augmentation& a);
  // The inputs of G_u: the true densities, or the fine G_rho's from the true renders.
  std::pair<Var, Var> inputs(Tape& tape, bool fromGrho, const render::RenderSettings& settings);

  Context& context_;
  networks::NetworkConfig config_;
  const dataset::SceneDataset& data_;
  Weights weights_{};
  int64_t finetuneSteps_ = 0;
  networks::VelocityGenerator generator_;
  std::unique_ptr<networks::DensityGenerator> grho_;
  render::ViewSet lossViews_;
  LookSlot look_;
  Var current_, next_, inflow_, velocity_, flags_;
  physics::AdvectionParams advection_;
  std::vector<std::unique_ptr<physics::FlagGrid>> grids_;  // one per recording, rebuilt from flags_ each submit
};

}  // namespace smokesvd::train
