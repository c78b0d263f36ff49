// Running sums of an evaluation and their summary as metrics.json and metrics.csv show it (docs/evaluation.md).
//
// Image metrics are computed per frame and view, for three candidates against the view's reference: ours (the
// render of the reconstruction), the all-black image (floor_black) and the input view's reference used as this
// view (floor_input, mirrored where the view says so; none at the input view itself). A view's figure is the
// mean over its frames; a group's (input, side, novel) the mean over its views. Temporal metrics are those of
// temporal_metrics.h on four sequences per view: ours, the reference, and the two floors.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/eval/eval_views.h"
#include "pipeline/eval/image_metrics.h"
#include "pipeline/eval/temporal_metrics.h"

namespace smokesvd::eval {

enum Candidate { kOurs = 0, kFloorBlack = 1, kFloorInput = 2 };
enum Sequence { kSequenceOurs = 0, kSequenceReference = 1, kSequenceBlack = 2, kSequenceInput = 3 };

struct ImageMeans {
  double rmse = 0, psnr = 0, ssim = 0;
  int count = 0;
  void add(const ImageScore& score);
  std::optional<std::array<double, 3>> means() const;  // rmse, psnr, ssim; nothing when count is 0
};

struct ViewTally {
  std::array<ImageMeans, 3> image;                 // by Candidate
  std::array<TemporalAccumulator, 4> temporal;     // by Sequence
};

struct VolumeTally {
  double densityOurs = 0, densityZero = 0;
  int densityFrames = 0;
  double velocityOurs = 0, velocityZero = 0;
  int velocityFrames = 0;
  double divergenceOurs = 0, divergenceTruth = 0, gradientOurs = 0, gradientTruth = 0;
  int motionFrames = 0;  // frames whose velocity is an estimate (all but the last of a clip of more than one)
  bool truth = false;
};

struct Summary {
  nlohmann::json image, temporal, volume;
  std::vector<std::vector<std::string>> csvRows;  // metrics.csv, without its header
};

Summary summarise(const std::vector<EvalView>& views, const std::vector<ViewTally>& tallies, const VolumeTally& volume,
                  const std::string& units);

// metrics.csv's header row.
std::vector<std::string> metricsCsvHeader();

}  // namespace smokesvd::eval
