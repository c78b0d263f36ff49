// Training G_rho (paper eq. 7):
//   L = l_rho ||rho - rho*||^2 + l_ds sum_k ||rho_k - rho*||^2 / K
//     + l_in sum_{a in A} ||R(rho, a) - R(rho*, a)||^2 / |A| + l_un sum_{a not in A} ||R(rho, a) - R(rho*, a)||^2 / |not A|
// over the 16 view slots, rho = G_rho(the true renders R(rho*, a) for a in A, zero elsewhere), rho_k the
// deep-supervision heads. Renders are made in the step by the differentiable renderer with the sample's
// own look. The fine variant always gives all 16 views; the coarse one the view sets of the progressive
// refinement (front and side: half the samples; and the near views: a quarter; and the mid views: a
// quarter), except for a share options.extra_view_probability of random larger sets. Validation: the mean render PSNR of all 16 views (fine), or of
// the 14 other views given the front and side, and given the front alone (coarse), and the density RMSE.
//
// Inference-like views (fine only, options.inference_views: the share of such samples): the views the
// reconstruction gives the fine G_rho after refinement -- the true front view, the side view (the true one,
// or with probability options.mirrored_side the mirrored front view, a stand-in for the synthesised side
// view), and at the 14 other slots the renders of the frozen coarse G_rho's density of those two. The loss
// stays against the true density and renders. Validation then also reports the 14 other views' PSNR of the
// fine density and of the coarse one from such inputs (what refinement gains over none), per side view.
#pragma once

#include <memory>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/train/look_slot.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

class GrhoTrainer : public StageTrainer {
 public:
  GrhoTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
              const std::filesystem::path& models);

  modules::Module& model() override { return generator_.net(); }
  // The look (unlit, lit) times the kind of input views: one recording each.
  std::vector<std::string> variants() const override;
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double density, renderInput, renderUnseen, deepSupervision;
  };
  // What the fine G_rho's input views are: the true renders, or the reconstruction's (see the top).
  enum class Inputs { True, InferenceTrueSide, InferenceMirroredSide };
  // Uploads a sample: density (and its mirror, for a mirrored side view), look and which slots are
  // inputs. Returns the variant: 1 for a lit look, plus 2 times the kind of input views.
  int upload(const std::vector<float>& density, const std::vector<float>& mirrored, const render::RenderSettings& look,
             const std::vector<bool>& inputs, Inputs kind);
  // The input views of the uploaded sample from its true renders [16, 1, h, w], and for inference-like
  // inputs the coarse G_rho's density they were rendered from.
  struct InputViews {
    Var views, coarse;
  };
  InputViews inputViews(Tape& tape, const Var& truth, const render::RenderSettings& settings);
  // Per-view squared errors of G_rho's renders for the uploaded sample, and of an all-black image.
  struct ViewErrors {
    std::vector<double> psnr, blackPsnr, coarsePsnr;  // coarsePsnr: inference-like inputs only
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
  double inferenceViews_ = 0, mirroredSide_ = 0;
  Inputs inputs_ = Inputs::True;
  networks::DensityGenerator generator_;
  std::unique_ptr<networks::DensityGenerator> coarse_;  // inference-like views only
  render::ViewSet fronts_;                              // 16 front cameras: the mirrored front view
  LookSlot look_;
  Var density_, mirrored_, presence_, sqrtInputWeights_, sqrtUnseenWeights_;
  Var frontOnly_, sideOnly_, frontAndSide_, others_;   // [16] constant slot masks
};

}  // namespace smokesvd::train
