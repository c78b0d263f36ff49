// `smokesvd eval`: how good a reconstruction is, against a simulated truth or against calibrated footage, every
// figure beside the trivial floors measured the same way (docs/evaluation.md):
//   OUT/metrics.json     every figure with its floors, and what it was measured on (data, views, region, resolution, units)
//   OUT/metrics.csv      the same figures, one row per view group and metric
//   OUT/per_frame.csv    RMSE, PSNR and SSIM of ours and of both floors per frame and view
//   OUT/comparison.png   reference | ours | error per view, for a few frames
// Files are written under temporary names and renamed; nothing else in OUT is touched.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/eval/eval_views.h"
#include "pipeline/eval/footage_references.h"
#include "runtime/context.h"

namespace smokesvd::eval {

struct EvalOptions {
  std::filesystem::path reconstruction, out;
  std::filesystem::path truth;             // a simulated scene, or
  std::filesystem::path cameras, videos;   // a calibration file and the folder of its videos
  std::vector<std::string> views;          // orbit slots (truth) or camera names (footage); empty: all
  Region region = Region::Box;             // footage only
  int width = 270;                         // footage, Region::Frame
  int supersample = 2;                     // footage: rays per pixel along each axis
  Units units = Units::Mapped;
  int sheetFrames = 3;
  bool quiet = false;
};

// Runs the evaluation, writes the files above and returns metrics.json's content. Errors (a folder that is not a
// reconstruction, a truth of another resolution or frame count, a calibration without the needed fields, a
// missing video) name the file and what was expected, before anything is written.
nlohmann::json runEvaluation(Context& context, const EvalOptions& options);

}  // namespace smokesvd::eval
