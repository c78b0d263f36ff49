// Training G_rho (paper eq. 7):
//   L = l_rho ||rho - rho*||^2 + l_ds sum_k ||rho_k - rho*||^2 / K
//     + l_in sum_{a in A} ||R(rho, a) - R(rho*, a)||^2 / |A| + l_un sum_{a not in A} ||R(rho, a) - R(rho*, a)||^2 / |not A|
// over the 16 view slots, rho = G_rho(the true renders R(rho*, a) for a in A, zero elsewhere), rho_k the
// deep-supervision heads. Renders are made in the step by the differentiable renderer with the sample's
// own look. The fine variant always gives all 16 views; the coarse one the view sets of the progressive
// refinement (front and side: half the samples; and the near views: a quarter; and the mid views: a
// quarter), except for a share options.extra_view_probability of random larger sets. Validation: the mean render PSNR of all 16 views (fine), or of
// the 14 other views given the front and side, and given the front alone (coarse), and the density RMSE.
#pragma once

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/train/look_slot.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

class GrhoTrainer : public StageTrainer {
 public:
  GrhoTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data);

  modules::Module& model() override { return generator_.net(); }
  std::vector<std::string> variants() const override { return {"unlit", "lit"}; }
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double density, renderInput, renderUnseen, deepSupervision;
  };
  // Uploads a sample: density, look and which slots are inputs. Returns the variant.
  int upload(const std::vector<float>& density, const render::RenderSettings& look, const std::vector<bool>& inputs);
  // Per-view squared errors of G_rho's renders for the uploaded sample, and of an all-black image.
  struct ViewErrors {
    std::vector<double> psnr, blackPsnr;
    double densityRmse = 0;
  };
  ViewErrors evaluate(int variant);
  std::vector<bool> drawCoarseViews(diffusion::Gaussian& random) const;

  Context& context_;
  networks::NetworkConfig config_;
  const dataset::SceneDataset& data_;
  Weights weights_{};
  bool fine_ = true;
  double extraViewProbability_ = 0;
  networks::DensityGenerator generator_;
  LookSlot look_;
  Var density_, presence_, sqrtInputWeights_, sqrtUnseenWeights_;
};

}  // namespace smokesvd::train
