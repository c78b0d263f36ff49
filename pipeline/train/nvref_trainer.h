// Training NvRef (paper eq. 8). A sample is a frame t >= 2 and a refinement stage of Algorithm 2 (near,
// mid or far, each a third of the samples): the coarse G_rho reconstructs the density from the true
// renders of the views known before that stage (front and side; then the near views; then the mid
// ones), and NvRef refines the renders of that density at four of the stage's views:
//   L = l_mse ||w_f - w||^2 + l_l1 |w_f - w| + l_res mean(res)^2 + l_sp ||H(w_f) - H(w)||^2
//     + l_psnr (PSNR(w_f, w_r) - PSNR(w, w_r))^2
// w the true render, w_r the coarse render, H the row sums (nets/functional/losses.h). The refined
// images of the two previous frames are stood in for by the true renders of those frames (and, for a
// tenth of the samples, by the coarse render itself, as at frames 0 and 1 where no previous refined
// image exists). Validation: the PSNR of the refined and of the unrefined renders against the truth at
// the near, mid and far views.
#pragma once

#include <memory>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/networks/refiner.h"
#include "pipeline/render/view_set.h"
#include "pipeline/train/look_slot.h"
#include "pipeline/train/sample_draw.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

class NvRefTrainer : public StageTrainer {
 public:
  NvRefTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
               const std::filesystem::path& models);

  modules::Module& model() override { return refiner_.net(); }
  std::vector<std::string> variants() const override { return {"unlit", "lit"}; }
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double mse, l1, meanResidual, rowSum, psnrGap;
  };
  // The batch the recordings read: N target slots of one stage.
  struct Batch {
    explicit Batch(Context& context, const Preset& preset, int views);
    int views;
    render::ViewSet targets, around;  // the N target views; the 2N views at -beta and +beta
    Var current, previous, beforePrevious, known, usePrevious;
  };
  int upload(Batch& batch, const dataset::SceneEntry& scene, int frame, const Augmentation& a, int stage,
             const std::vector<int>& slots, const std::vector<float>& usePrevious);
  struct Images {
    Var truth, render, refined, residual;
  };
  Images forward(Tape& tape, Batch& batch, const render::RenderSettings& settings);

  Context& context_;
  networks::NetworkConfig config_;
  const dataset::SceneDataset& data_;
  Weights weights_{};
  double beta_ = 22.5;
  networks::Refiner refiner_;
  std::unique_ptr<networks::DensityGenerator> coarse_;
  LookSlot look_;
  Batch batch_;
};

}  // namespace smokesvd::train
