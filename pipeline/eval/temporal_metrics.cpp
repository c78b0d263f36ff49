#include "pipeline/eval/temporal_metrics.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "runtime/error.h"

#ifdef SMOKESVD_HAVE_OPENCV
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#endif

namespace smokesvd::eval {
namespace {

#ifdef SMOKESVD_HAVE_OPENCV
cv::Mat asMat(const media::Image& image) {
  return cv::Mat(image.height, image.width, CV_32FC1, const_cast<float*>(image.values.data()));
}

struct PairScores {
  double flowMagnitude = 0, warpError = 0;
};

PairScores scorePair(const media::Image& first, const media::Image& second) {
  const cv::Mat a = asMat(first), b = asMat(second);
  // Farneback's polynomial fit expects 8-bit levels (its solver regularises with a fixed epsilon): the flow is
  // computed on the images scaled by 255, in float.
  cv::Mat a255, b255, flow;
  a.convertTo(a255, CV_32F, 255.0);
  b.convertTo(b255, CV_32F, 255.0);
  cv::calcOpticalFlowFarneback(a255, b255, flow, 0.5, 3, 15, 3, 5, 1.2, 0);
  cv::Mat mapX(a.size(), CV_32FC1), mapY(a.size(), CV_32FC1);
  double magnitudes = 0;
  for (int r = 0; r < a.rows; ++r)
    for (int c = 0; c < a.cols; ++c) {
      const cv::Vec2f f = flow.at<cv::Vec2f>(r, c);
      magnitudes += std::hypot(static_cast<double>(f[0]), static_cast<double>(f[1]));
      mapX.at<float>(r, c) = static_cast<float>(c) + f[0];
      mapY.at<float>(r, c) = static_cast<float>(r) + f[1];
    }
  cv::Mat warped;
  cv::remap(b, warped, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0));
  double squares = 0;
  int64_t valid = 0;
  for (int r = 0; r < a.rows; ++r)
    for (int c = 0; c < a.cols; ++c) {
      const float x = mapX.at<float>(r, c), y = mapY.at<float>(r, c);
      if (x < 0 || y < 0 || x > static_cast<float>(a.cols - 1) || y > static_cast<float>(a.rows - 1)) continue;
      const double d = static_cast<double>(a.at<float>(r, c)) - static_cast<double>(warped.at<float>(r, c));
      squares += d * d;
      ++valid;
    }
  return {magnitudes / static_cast<double>(a.rows * a.cols), valid > 0 ? squares / static_cast<double>(valid) : 0.0};
}
#endif

}  // namespace

bool opticalFlowAvailable() {
#ifdef SMOKESVD_HAVE_OPENCV
  return true;
#else
  return false;
#endif
}

void TemporalAccumulator::add(const media::Image& frame) {
  if (frame.channels != 1) throw Error("temporal metrics: frames must be gray");
  if (previous_ && (previous_->width != frame.width || previous_->height != frame.height))
    throw Error("temporal metrics: a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                " frame follows a " + std::to_string(previous_->width) + "x" + std::to_string(previous_->height) + " one");
#ifdef SMOKESVD_HAVE_OPENCV
  if (previous_) {
    const PairScores s = scorePair(*previous_, frame);
    flowMagnitudes_.push_back(s.flowMagnitude);
    warpErrors_.push_back(s.warpError);
  }
#endif
  previous_ = frame;
}

TemporalScores TemporalAccumulator::finish() const {
  TemporalScores s;
  s.available = opticalFlowAvailable();
  s.pairs = static_cast<int>(flowMagnitudes_.size());
  if (s.pairs == 0) return s;
  const double n = s.pairs;
  for (std::size_t i = 0; i < flowMagnitudes_.size(); ++i) {
    s.warpError += warpErrors_[i] / n;
    s.flowMean += flowMagnitudes_[i] / n;
    s.flowMax = std::max(s.flowMax, flowMagnitudes_[i]);
  }
  for (const double m : flowMagnitudes_) s.flowStd += (m - s.flowMean) * (m - s.flowMean) / n;
  s.flowStd = std::sqrt(s.flowStd);
  return s;
}

}  // namespace smokesvd::eval
