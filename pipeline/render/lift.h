// Lifting: every view's image spread along its camera rays into the volume, the input encoding of the density
// network (views become channels; a missing view is simply an image of zeros), and its adjoint.
//   lifted[v, z, y, x] = image_v(projection of the voxel centre into camera v)   (bilinear, zero outside)
#pragma once

#include "pipeline/render/view_set.h"
#include "runtime/stream.h"

namespace smokesvd::render {

// images [V, 1, h, w] -> lifted [V, D, H, W] (or [1, V, D, H, W]); `grid` is the volume size.
void lift(Stream& stream, const Tensor& images, const ViewSet& views, const GridSize& grid, const Tensor& lifted);
// gradLifted (shape of lifted) -> gradImages [V, 1, h, w] (written, not accumulated).
void liftBackward(Stream& stream, const Tensor& gradLifted, const ViewSet& views, const GridSize& grid,
                  const Tensor& gradImages);

}  // namespace smokesvd::render
