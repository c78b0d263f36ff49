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
  // Every ray runs along a row of voxel centres and every voxel row projects onto a pixel row: orthographic
  // cameras looking horizontally, one pixel row per voxel row (origin per v (0, -1, 0), no vertical component
  // in origin per u or in the direction, projection row 1 (0, -1, 0, s)), at integer heights (origin y and
  // s). Orbit cameras with the volume's height in pixels are such views; pixel row r then lies in voxel plane
  // s - 1 - r, and kernels may give each voxel plane to one invocation (shaders/render/*_rows.comp).
  bool raysInVoxelRows = false;
};

// Uploads `cameras` (at least one; all with the same image size, else Error).
ViewSet uploadViews(Context& context, std::span<const Camera> cameras);
// Uploads other cameras (as many, of the same image size, and whose rays run in voxel rows where the
// uploaded ones' do: a recording may have chosen its kernels by that) into the table, so that a recording
// made with `views` renders from them at its next submit.
void rewriteViews(const ViewSet& views, std::span<const Camera> cameras);

// The grid size of a volume tensor [..., D, H, W] whose leading dimensions are all 1 (Error naming `what`
// and the shape otherwise).
GridSize volumeGrid(const Tensor& volume, const char* what);

}  // namespace smokesvd::render
