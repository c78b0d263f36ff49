// Image metrics of gray image pairs, computed on the GPU (docs/evaluation.md):
//   mse  = mean over the pixels of (a - b)^2,   rmse = sqrt(mse),
//   psnr = 10 log10(1 / mse) dB (peak value 1; 100 dB when mse <= 1e-10, so identical images stay finite),
//   ssim = the mean of the SSIM map of shaders/eval/ssim.comp (Wang et al. 2004: Gaussian window 11 x 11,
//          sigma 1.5, K1 0.01, K2 0.03, L 1, at the positions where the window lies inside the image).
// Values are taken as they are (callers clamp images to [0, 1] as PNGs would); both images of a pair have one
// size of at least 11 x 11 pixels.
#pragma once

#include <span>
#include <vector>

#include "pipeline/media/image.h"
#include "runtime/context.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::eval {

constexpr int kSsimWindow = 11;
constexpr double kPsnrCap = 100.0;

struct ImageScore {
  double mse = 0, ssim = 0;
  double rmse() const;
  double psnr() const;
};

double psnrOf(double mse);

// mse[n] and ssim[n] of the pairs (a[n], b[n]) of two stacks [N, H, W] (device tensors; outputs [N]).
void recordImageScores(Stream& stream, const Tensor& a, const Tensor& b, const Tensor& mse, const Tensor& ssim);

struct ImagePair {
  const media::Image* a = nullptr;
  const media::Image* b = nullptr;
};

// The scores of every pair, in order; pairs of one size go to the GPU as one stack. Error if the two images of
// a pair differ in size, are smaller than 11 x 11 or are not gray.
std::vector<ImageScore> compareImages(Context& context, std::span<const ImagePair> pairs);

}  // namespace smokesvd::eval
