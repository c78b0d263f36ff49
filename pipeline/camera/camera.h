// Cameras: one model for rendering, lifting and evaluation. A Camera is a pixel -> ray map and a point ->
// pixel projection, both expressed in GRID coordinates, so the kernels never see world space.
//
// Grid coordinates (docs/conventions.md): a volume tensor [D, H, W] = [z, y, x] spans the box [0, W] x [0, H] x
// [0, D]; its element [k][j][i] (x index i, y index j, z index k) is centred at (i + 1/2, j + 1/2, k + 1/2).
// y is up. Lengths are in voxels.
// Pixel coordinates: an image is [height, width], row 0 at the top; pixel (row r, column c) is centred
// at (u, v) = (c + 1/2, r + 1/2).
//
// Orbit cameras (orthographic) turn about the vertical line through the volume centre. At angle a the
// camera looks along  forward = (-sin a, 0, cos a),  with image right = (cos a, 0, sin a) and up = +y.
// a = 0 is the front (input) view: it looks along +z (the slice z = 0 is nearest the camera), columns run
// along +x and rows down -y, so column c of the image is voxel column x = c when the sizes match.
// a = 90 deg is the side view: it looks along -x, columns run along +z. The image window is the volume's
// x extent by its y extent (W x H voxels) centred on the volume centre, whatever the angle.
// Calibrated perspective cameras come from NeRF-style JSON (pipeline/camera/calibration.h).
#pragma once

#include <array>
#include <glm/mat4x3.hpp>
#include <optional>
#include <vector>

#include "runtime/geometry.h"

namespace smokesvd {

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit length in grid coordinates
};

struct Camera {
  int width = 0, height = 0;  // image size in pixels
  bool perspective = false;
  // Ray through pixel coordinates (u, v): origin = origin + u originPerU + v originPerV,
  // direction = normalize(direction + u directionPerU + v directionPerV).
  Vec3 origin{}, originPerU{}, originPerV{};
  Vec3 direction{}, directionPerU{}, directionPerV{};
  // Grid point p -> (a, b, c) = projection * (p, 1); pixel coordinates (u, v) = (a / c, b / c). c > 0 in
  // front of the camera (c = 1 for orthographic cameras). 3 rows, 4 columns (GLM names the columns first).
  glm::dmat4x3 projection{0.0};

  Ray ray(double u, double v) const;
  // Pixel coordinates of a grid point, or nothing if it lies behind a perspective camera.
  std::optional<std::array<double, 2>> project(const Vec3& point) const;
  // Unit viewing direction at the image centre (grid coordinates).
  Vec3 forward() const;
};

// The orthographic orbit camera at `angleDegrees` for a volume of `grid`, rendering width x height pixels.
Camera orbitCamera(double angleDegrees, const GridSize& grid, int width, int height);
// `views` angles evenly on [0, 180): i * 180 / views degrees.
std::vector<double> orbitAngles(int views);
std::vector<Camera> orbitCameras(const std::vector<double>& anglesDegrees, const GridSize& grid, int width,
                                 int height);

// The camera whose image is the window [x0, x0 + windowWidth] x [y0, y0 + windowHeight] (pixel coordinates of
// `camera`'s image; it may extend past the image) resampled to width x height pixels: its pixel (u, v) sees
// what `camera` sees at (x0 + u windowWidth / width, y0 + v windowHeight / height). Perspective or not as
// `camera` is; rays and projection stay exact, so a crop of the footage and a render through this camera
// cover the same part of the scene.
Camera windowCamera(const Camera& camera, double x0, double y0, double windowWidth, double windowHeight, int width,
                    int height);

// The orbit angle (degrees, in (-180, 180]) of a camera's central viewing direction about the vertical axis,
// in the convention above (0 = looking along +z, 90 = looking along -x).
double orbitAngleOf(const Camera& camera);

}  // namespace smokesvd
