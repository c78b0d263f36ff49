// Up- and down-sampling of N,C,H,W and N,C,D,H,W float32 tensors by an integer factor k along every
// spatial axis, with PyTorch's F.interpolate semantics, align_corners=False:
//   up:    F.interpolate(x, scale_factor=k, mode=...)     every spatial size s becomes s k
//   down:  F.interpolate(x, scale_factor=1/k, mode=...)   every spatial size s becomes floor(s / k)
// Nearest: up repeats each element k times per axis; down keeps element o k (the first of each block).
// Linear (bilinear in 2D, trilinear in 3D): up samples at (o + 1/2) / k - 1/2 clamped at 0; down
// samples at (o + 1/2) k - 1/2, i.e. the average of the two middle elements of each block for even k
// and the middle element for odd k (no area averaging, no antialiasing).
// Kernels (shaders/nn/resample_*.comp): upsampling of widths divisible by 4 runs in one pass; everything
// else runs as one pass per spatial axis (separable stencils), with intermediate tensors.
#pragma once

#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::ops {

enum class ResampleMode { Nearest = 0, Linear = 1 };

struct Resample {
  ResampleMode mode = ResampleMode::Linear;
  bool down = false;  // false: upsample by factor, true: downsample by factor
  int factor = 2;     // >= 1
};

// The output shape for input shape x. Throws Error unless x is 4D or 5D, non-empty, factor >= 1 and
// every downsampled size is at least 1.
Shape resampledShape(const Shape& x, const Resample& resample);

void resampleForward(Stream& stream, const Resample& resample, const Tensor& x, const Tensor& y);
// gx = the transpose of the forward applied to gy (gx has the input's shape).
void resampleBackward(Stream& stream, const Resample& resample, const Tensor& gy, const Tensor& gx);

}  // namespace smokesvd::ops
