// A reconstruction against the simulated truth it came from, view for view: the render PSNR of the
// reconstructed density against the truth's at the input view (0 degrees), the side view (90) and the
// novel views (45, 67.5, 112.5, 135), each the mean over frames of per-image PSNR (data range 1, whole
// preset-size image), and the density RMSE (networks' units), beside two floors measured the same way:
// an all-black image, and the truth's input view used as every other view (mirrored for the side).
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "runtime/context.h"

namespace smokesvd::reconstruct {

struct TruthComparison {
  double inputPsnr = 0, sidePsnr = 0, novelPsnr = 0, densityRmse = 0;
  double blackInput = 0, blackSide = 0, blackNovel = 0;
  double frontAsSide = 0, frontAsNovel = 0;
  int frames = 0;
  nlohmann::json toJson() const;
};

// `truth`: a simulation folder whose scene renders with the preset's reference look (its render
// absorption equal to the preset's, ambient 1, no light), so that its densities are in the networks' units.
TruthComparison compareWithTruth(Context& context, const std::filesystem::path& reconstruction,
                                 const std::filesystem::path& truth, const std::string& preset);

}  // namespace smokesvd::reconstruct
