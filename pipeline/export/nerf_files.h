// The orbit views of every frame as NeRF / 3D Gaussian Splatting datasets, one folder per frame:
//   OUT/frame_NNNN/images/view_VV.png     the run's renders/view_VV/NNNN.png as 8-bit RGB (gray in every channel)
//   OUT/frame_NNNN/transforms.json        nerfstudio: camera_model OPENCV (no distortion), fl_x, fl_y, cx, cy, w,
//                                         h, and per view file_path (with its extension) and transform_matrix
//   OUT/frame_NNNN/transforms_train.json  NeRF-synthetic (the original NeRF, 3D Gaussian Splatting's loader):
//   OUT/frame_NNNN/transforms_test.json   camera_angle_x and file_path without extension; the test file holds
//                                         no frames. Written only when the pixels are square (fx == fy).
// The cameras are the pinhole stand-ins of nerf_cameras.h, the same for every frame, in the world of
// world_placement.h. Each transforms.json also carries a "smokesvd" object with the exact orthographic views.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "pipeline/export/world_placement.h"
#include "pipeline/sim/saved_run.h"

namespace smokesvd::exporters {

nlohmann::json writeNerf(const sim::SavedRun& run, const WorldPlacement& placement, double maxErrorPixels,
                         const std::filesystem::path& out);

}  // namespace smokesvd::exporters
