// Differentiable up- and down-sampling by an integer factor (autograd wrappers of nets/ops/resample.h)
// on N,C,H,W and N,C,D,H,W, PyTorch's F.interpolate with align_corners=False:
//
//   Var upsample(Tape& tape, const Var& x, int factor, ResampleMode mode);
//       F.interpolate(x, scale_factor=factor, mode=...); every spatial size s becomes s * factor
//   Var downsample(Tape& tape, const Var& x, int factor, ResampleMode mode);
//       F.interpolate(x, scale_factor=1/factor, mode=...); every spatial size s becomes floor(s / factor)
//
// mode: ResampleMode::Nearest ('nearest') or ResampleMode::Linear ('bilinear' for 4D, 'trilinear' for
// 5D). Nearest downsampling keeps element o * factor of each axis (the first of each block); linear
// downsampling samples at (o + 1/2) factor - 1/2: the mean of the two middle elements of each block for
// even factors, the middle element for odd ones (not an area average). See docs/nn-layers.md.
// Registered for `smokesvd op` as upsample and downsample (attrs factor, mode = nearest | linear).
#pragma once

#include "nets/autograd/tape.h"
#include "nets/ops/resample.h"

namespace smokesvd::fn {

using ops::ResampleMode;

Var upsample(Tape& tape, const Var& x, int factor, ResampleMode mode);
Var downsample(Tape& tape, const Var& x, int factor, ResampleMode mode);

}  // namespace smokesvd::fn
