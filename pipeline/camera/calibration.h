// Calibrated perspective cameras from NeRF-style JSON (the ScalarFlow info.json layout).
//
// File fields: "train_videos" / "test_videos": lists of views with "file_name", "camera_angle_x"
// (horizontal field of view, radians), "camera_hw" ([height, width] in pixels), "transform_matrix"
// (camera-to-world 4x4, OpenGL/NeRF convention: the camera looks down its -z, +y is up, +x is right),
// optional "frame_rate" and "frame_num"; "voxel_matrix" (4x4) and "voxel_scale" ([x, y, z] metres) place the
// volume box in the world.
//
// Grid -> world (the reading of these files by the public code that distributes them, which exchanges the
// first and third columns of voxel_matrix): voxel_matrix acts on box coordinates in tensor order (z, y, x):
//     world = voxel_matrix * (scale_z * gz / D, scale_y * gy / H, scale_x * gx / W, 1)
// with (gx, gy, gz) grid coordinates (pipeline/camera/camera.h). For the ScalarFlow file this maps grid +x to
// world +x and grid +z to world -z, so the centre camera (train02) looks along grid +z: orbit angle ~0.
//
// Pixel rays follow NeRF: for pixel coordinates (u, v) of an image of width w (the focal length scales with
// the rendered width: f = w / (2 tan(camera_angle_x / 2)), square pixels), the camera-space direction is
// ((u - w/2) / f, -(v - h/2) / f, -1); u, v are pixel centres (c + 1/2, r + 1/2).
#pragma once

#include <filesystem>
#include <glm/mat4x4.hpp>
#include <string>
#include <vector>

#include "pipeline/camera/camera.h"

namespace smokesvd {

struct CalibratedView {
  std::string fileName;
  double cameraAngleX = 0;        // horizontal field of view, radians
  int height = 0, width = 0;      // calibrated image size (camera_hw)
  glm::dmat4 cameraToWorld{1.0};
  double frameRate = 0;           // 0 when absent
  int frameCount = 0;             // 0 when absent
};

struct VolumeBox {
  glm::dmat4 voxelMatrix{1.0};
  Vec3 scale{1, 1, 1};            // metres along box x, y, z
  // Grid coordinates of `grid` -> world (see above).
  glm::dmat4 gridToWorld(const GridSize& grid) const;
};

struct Calibration {
  std::vector<CalibratedView> views;  // train_videos first, then test_videos
  VolumeBox box;
  const CalibratedView& view(const std::string& fileName) const;  // Error listing names if absent
};

// Reads a NeRF-style calibration file. Errors name the file, the field and what was expected.
Calibration readCalibration(const std::filesystem::path& path);

// The perspective camera of `view` for a volume `grid` placed by `box`, rendering `width` pixels wide
// (0: the calibrated width); the height keeps the calibrated aspect ratio.
Camera calibratedCamera(const CalibratedView& view, const VolumeBox& box, const GridSize& grid, int width = 0);

// The eight corners of the grid box [0,W]x[0,H]x[0,D] in grid coordinates, corner i = (i&1 ? W : 0,
// i&2 ? H : 0, i&4 ? D : 0).
std::array<Vec3, 8> gridCorners(const GridSize& grid);

}  // namespace smokesvd
