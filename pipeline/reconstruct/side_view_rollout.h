// SvDiff's own quality check (issue: a 40-frame autoregressive rollout): for held-out simulated scenes,
// the side view of every frame is synthesised exactly as a reconstruction does it (SvDiff-init for frames
// 0 and 1, then SvDiff conditioned on its own previous side views and the 90-degree renders of their
// coarse densities) from the true front views, and compared with the true side views: PSNR per frame
// (data range 1, whole preset-size images), beside the naive baseline of the mirrored front view and the
// all-black floor (on mostly black images an all-black side view scores high), and the true side view of
// the frame before, copied (what a synthesiser that leans on true history can reach by copying it).
// Front and side views are renders of the simulated densities with each scene's look in the networks'
// units (pipeline/dataset/scene_dataset.h).
// With RolloutHistory::Truth every frame is conditioned instead on the true side views of the previous
// frames and the renders of their densities reconstructed from them (teacher forcing): what each frame's
// synthesis gets right from true history, to tell errors that accumulate over the rollout (drift) from
// frames that are harder in themselves.
// The rollout can run on the training split instead, and keep its side views in a folder
// (pipeline/dataset/synthesised_side_views.h) for training NvRef on the side views inference gives it; a
// rollout into a folder that holds some scenes already reuses them, so a long one resumes.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/reconstruct/method_models.h"
#include "pipeline/reconstruct/side_view_stage.h"

namespace smokesvd::reconstruct {

struct RolloutResult {
  std::vector<double> psnr, mirrored, black;  // per frame, mean over scenes
  std::vector<double> previous;  // per frame from frame 1: the true side view of the frame before, copied
  int scenes = 0;
  int firstFrame = 0;  // the scene frame of the rollout's frame 0
  bool trueHistory = false;  // conditioned on the true side views of the previous frames
  double mean() const;
  double mirroredMean() const;
  double blackMean() const;
  double previousMean() const;  // frames 1 on
  double firstTen() const;
  double lastTen() const;
  double mirroredFirstTen() const;
  double mirroredLastTen() const;
  nlohmann::json toJson() const;
};

enum class RolloutHistory { Own, Truth };

struct RolloutScenes {
  bool training = false;                // the training split's scenes, not the held-out ones
  std::filesystem::path keepSideViews;  // when set: the side views kept there, and those already there reused
};

// Rolls out `frames` frames from scene frame `firstFrame` (0: from the start of the simulation; later: footage
// that begins with smoke already in view, SvDiff-init starting on the frames there) on up to `scenes` validation
// scenes (or training scenes) that have firstFrame + frames frames; with `progress`, a progress line over those
// scenes' frames on stderr (pipeline/progress.h).
RolloutResult sideViewRollout(Context& context, MethodModels& models, const dataset::SceneDataset& data, int firstFrame,
                              int frames, int scenes, const SideViewOptions& options, RolloutHistory history = RolloutHistory::Own,
                              bool progress = false, const RolloutScenes& from = {});

}  // namespace smokesvd::reconstruct
