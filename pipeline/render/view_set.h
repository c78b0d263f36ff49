// Cameras on the device: a ViewSet is the camera table every render, lift and their adjoints read
// (9 vec4 per view, layout in shaders/render/camera.glsl), plus the image size all its views share.
#pragma once

#include <span>

#include "pipeline/camera/camera.h"
#include "runtime/tensor.h"

namespace smokesvd::render {

struct ViewSet {
  Tensor table;  // [views, 36] float32
  int views = 0;
  int width = 0, height = 0;
};

// Uploads `cameras` (at least one; all with the same image size, else Error).
ViewSet uploadViews(Context& context, std::span<const Camera> cameras);
// Uploads other cameras (as many, of the same image size) into the table, so that a recording made
// with `views` renders from them at its next submit.
void rewriteViews(const ViewSet& views, std::span<const Camera> cameras);

// The grid size of a volume tensor [..., D, H, W] whose leading dimensions are all 1 (Error naming `what`
// and the shape otherwise).
GridSize volumeGrid(const Tensor& volume, const char* what);

}  // namespace smokesvd::render
