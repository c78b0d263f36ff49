// Temporal metrics of one image sequence (docs/evaluation.md), from dense optical flow F_t between frames t and
// t + 1 by OpenCV's Farneback method (pyramid scale 0.5, 3 levels, window 15, 3 iterations, poly_n 5,
// poly_sigma 1.2, no flags), so that I_t(p) ~ I_{t+1}(p + F_t(p)):
//   flow magnitude   m_t = mean over the pixels p of |F_t(p)|, in pixels per frame at the image's resolution;
//                    flowMax, flowMean, flowStd = max, mean and population standard deviation of m_t over t;
//   warp error       e_t = mean over the valid pixels of (I_t(p) - W_t(p))^2, W_t(p) = I_{t+1}(p + F_t(p))
//                    sampled bilinearly, valid where p + F_t(p) lies inside the image; warpError = mean of e_t.
// A sequence of one frame has no pair: every figure is 0 and pairs is 0. Without OpenCV at build time
// (SMOKESVD_OPENCV off) nothing is computed and `available` is false.
#pragma once

#include <optional>
#include <vector>

#include "pipeline/media/image.h"

namespace smokesvd::eval {

struct TemporalScores {
  bool available = false;
  int pairs = 0;
  double warpError = 0, flowMax = 0, flowMean = 0, flowStd = 0;
};

// Whether this build has OpenCV's optical flow.
bool opticalFlowAvailable();

// Takes a sequence one frame at a time (gray, all of one size) and keeps only the previous frame.
class TemporalAccumulator {
 public:
  void add(const media::Image& frame);
  TemporalScores finish() const;

 private:
  std::optional<media::Image> previous_;
  std::vector<double> flowMagnitudes_, warpErrors_;  // one per pair
};

}  // namespace smokesvd::eval
