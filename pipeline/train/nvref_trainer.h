// Training NvRef (paper eq. 8). A sample is a frame t >= 2 and a refinement stage of Algorithm 2 (near,
// mid or far, each a third of the samples): the coarse G_rho reconstructs the density from the true
// renders of the views known before that stage (front and side; then the near views; then the mid
// ones), and NvRef refines the renders of that density at four of the stage's views:
//   L = l_mse ||w_f - w||^2 + l_l1 |w_f - w| + l_res mean(res)^2 + l_sp ||H(w_f) - H(w)||^2
//     + l_psnr (PSNR(w_f, r) - PSNR(w, r))^2
// w the true render, w_r the coarse render, H the row sums (nets/functional/losses.h), r the PSNR's
// reference: with options.psnr_reference = "render" (default) r = w_r, so the refined image is asked to
// lie as far from the render as the truth does; with "black" r = 0 and PSNR(x, 0) = 10 log10(1 / mean x^2),
// a term on the images' energy (the other reading of the paper's PSNR(w_f) - PSNR(w)). The refined
// images of the two previous frames are stood in for by the true renders of those frames (and, for a
// tenth of the samples, by the coarse render itself, as at frames 0 and 1 where no previous refined
// image exists). That teaches NvRef to copy the truth of the frame before, which inference does not have:
// there the history is NvRef's own output, and its errors feed back frame after frame. With
// options.history = "coarse" the history is instead the renders of the coarse G_rho's densities of
// those frames (reconstructed like the current one's); with "self" it is those renders refined by NvRef
// itself (without gradient, as the first frames are refined: each render standing in for its own
// history). At inference the side view is synthesised, not true: with probability
// options.mirrored_side (default 0) a sample's coarse density is reconstructed with the mirrored front
// view in the side slot instead (the front render of the x-mirrored volume), so that NvRef also learns
// from the blurrier, wrongly deep densities it is given in practice; with probability
// options.synthesised_side the side slot holds SvDiff's own side view of that frame, from a rollout of
// training scenes kept in the folder options.side_views (pipeline/dataset/synthesised_side_views.h; such
// samples are not augmented: the side views were synthesised for the scene as simulated), the side
// views inference gives it. Validation: the PSNR of the refined and of the unrefined renders against the
// truth at the near, mid and far views, with the true side view, (suffix _mirrored) with the mirrored
// front view and, where options.side_views holds held-out scenes, (suffix _synthesised) with SvDiff's.
// With options.earlier_views = "truth" (default) the views of the earlier stages are the true renders;
// inference has only its own images there, so with "coarse" each stage's density is reconstructed, as
// the reconstruction's progressive refinement does, from the input views and the renders at the earlier
// stages' slots of the density of the stage before (the refinement of those renders left out):
//   rho_near = G(front, side),  rho_mid = G(front, side, R(rho_near, near)),
//   rho_far = G(front, side, R(rho_near, near), R(rho_mid, mid)).
// options.stages (default ["near", "mid", "far"]) restricts the stages training draws; validation measures
// all three.
#pragma once

#include <array>
#include <memory>
#include <optional>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/dataset/synthesised_side_views.h"
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
  // The look (unlit, lit) times the side view of the coarse density (true, mirrored front view, synthesised)
  // and, with earlier_views "coarse", times the stage (its number of coarse reconstructions): variant =
  // look + 2 side + 6 stage.
  std::vector<std::string> variants() const override;
  int prepare(int64_t step, diffusion::Gaussian& random) override;
  LossTerms record(Tape& tape, int variant) override;
  std::vector<Metric> validate() override;
  std::string dataSummary() const override;
  double forwardFlops() override;

 private:
  struct Weights {
    double mse, l1, meanResidual, rowSum, psnrGap;
  };
  // What the coarse G_rho is given in the side slot.
  enum class Side { True, Mirrored, Synthesised };
  // One frame of a sample: t, t-1 or t-2.
  struct Frame {
    Var density;      // the true density
    Var mirrored;     // the same, mirrored in x (Side::Mirrored only)
    Var synthesised;  // [16, 1, h, w]: SvDiff's side view in the side slot, 0 elsewhere (Side::Synthesised only)
  };
  // The batch the recordings read: N target slots of one stage.
  struct Batch {
    explicit Batch(Context& context, const Preset& preset, int views);
    int views;
    // The N target views; the same followed by the 2N views at -beta and +beta: one render of a density at all
    // three (its light's shadow made once) where the refiner needs them.
    render::ViewSet targets, targetsAndAround;
    render::ViewSet fronts;           // 16 front cameras: the mirrored front view for every slot
    std::array<Frame, 3> frames;      // t, t-1, t-2
    Var known, usePrevious;     // [16] the slots known at the stage; [N] 0 where the render stands in for history
    Var knownWithoutSide;       // [16] known, less the side slot (a side view other than the true one)
    Var sideOnly;               // [16] 1 at the side slot, 0 elsewhere (constant)
    Var black;                  // [N, 1, h, w] zeros: the PSNR term's reference with psnr_reference "black"
    std::array<Var, 3> knownAt;     // [16] the slots known at stage s (constant; earlier_views "coarse")
    std::array<Var, 2> stageViews;  // [16] 1 at stage s's slots, s < 2 (constant; earlier_views "coarse")
    Side side = Side::True;
    int stage = 0;
  };
  int upload(Batch& batch, const dataset::SceneEntry& scene, int frame, const Augmentation& a, int stage,
             const std::vector<int>& slots, const std::vector<float>& usePrevious, Side side);
  struct Images {
    Var truth, render, refined, residual;
  };
  Images forward(Tape& tape, Batch& batch, const render::RenderSettings& settings);
  Var coarseDensity(Tape& tape, Batch& batch, const Frame& frame, const render::RenderSettings& settings);

  Context& context_;
  networks::NetworkConfig config_;
  const dataset::SceneDataset& data_;
  Weights weights_{};
  double beta_ = 22.5;
  double mirroredSide_ = 0.0, synthesisedSide_ = 0.0;
  std::optional<dataset::SynthesisedSideViews> sideViews_;  // options.side_views
  enum class History { Truth, Coarse, Self };
  History history_ = History::Truth;  // options.history
  bool psnrAgainstBlack_ = false;      // options.psnr_reference == "black"
  bool coarseEarlierViews_ = false;    // options.earlier_views == "coarse"
  std::vector<int> stages_{0, 1, 2};   // options.stages: the stages training draws (0 near, 1 mid, 2 far)
  networks::Refiner refiner_;
  std::unique_ptr<networks::DensityGenerator> coarse_;
  LookSlot look_;
  Batch batch_;
};

}  // namespace smokesvd::train
