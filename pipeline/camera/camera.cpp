#include "pipeline/camera/camera.h"

#include <numbers>

#include "runtime/error.h"

namespace smokesvd {

bool invertAffine(const Mat4& m, Mat4& inverse) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  if (std::abs(det) < 1e-300) return false;
  const Mat3 r = {(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                  (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                  (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
  inverse = identity4();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) inverse[4 * row + col] = r[3 * row + col];
    inverse[4 * row + 3] = -(r[3 * row] * m[3] + r[3 * row + 1] * m[7] + r[3 * row + 2] * m[11]);
  }
  return true;
}

Ray Camera::ray(double u, double v) const {
  return {origin + u * originPerU + v * originPerV, normalize(direction + u * directionPerU + v * directionPerV)};
}

std::optional<std::array<double, 2>> Camera::project(const Vec3& point) const {
  double row[3];
  for (int r = 0; r < 3; ++r)
    row[r] = projection[4 * r] * point[0] + projection[4 * r + 1] * point[1] + projection[4 * r + 2] * point[2] +
             projection[4 * r + 3];
  if (row[2] <= 0) return std::nullopt;
  return std::array<double, 2>{row[0] / row[2], row[1] / row[2]};
}

Vec3 Camera::forward() const { return ray(0.5 * width, 0.5 * height).direction; }

Camera orbitCamera(double angleDegrees, const GridSize& grid, int width, int height) {
  if (width <= 0 || height <= 0 || grid.width <= 0 || grid.height <= 0 || grid.depth <= 0)
    throw Error("orbit camera: image " + std::to_string(width) + "x" + std::to_string(height) + " and grid " +
                std::to_string(grid.depth) + "x" + std::to_string(grid.height) + "x" + std::to_string(grid.width) +
                " must all be positive");
  const double a = angleDegrees * std::numbers::pi / 180.0;
  const Vec3 forward = {-std::sin(a), 0.0, std::cos(a)};
  const Vec3 right = {std::cos(a), 0.0, std::sin(a)};
  const Vec3 up = {0.0, 1.0, 0.0};
  const double windowWidth = static_cast<double>(grid.width);
  const double windowHeight = static_cast<double>(grid.height);
  const Vec3 centre = grid.centre();
  const double backOff = length(centre) + 1.0;  // starts every ray outside the volume

  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.perspective = false;
  camera.origin = centre - backOff * forward - (0.5 * windowWidth) * right + (0.5 * windowHeight) * up;
  camera.originPerU = (windowWidth / width) * right;
  camera.originPerV = (-windowHeight / height) * up;
  camera.direction = forward;
  // u = ((p - centre) . right + W/2) * width / W;  v = (H/2 - (p - centre) . up) * height / H.
  const double su = width / windowWidth, sv = height / windowHeight;
  camera.projection = {su * right[0], su * right[1], su * right[2], su * (0.5 * windowWidth - dot(centre, right)),
                       -sv * up[0],   -sv * up[1],   -sv * up[2],   sv * (0.5 * windowHeight + dot(centre, up)),
                       0.0,           0.0,           0.0,           1.0};
  return camera;
}

std::vector<double> orbitAngles(int views) {
  if (views <= 0) throw Error("orbit angles: the number of views must be positive, got " + std::to_string(views));
  std::vector<double> angles;
  for (int i = 0; i < views; ++i) angles.push_back(180.0 * i / views);
  return angles;
}

std::vector<Camera> orbitCameras(const std::vector<double>& anglesDegrees, const GridSize& grid, int width,
                                 int height) {
  std::vector<Camera> cameras;
  for (double angle : anglesDegrees) cameras.push_back(orbitCamera(angle, grid, width, height));
  return cameras;
}

double orbitAngleOf(const Camera& camera) {
  const Vec3 f = camera.forward();
  return std::atan2(-f[0], f[2]) * 180.0 / std::numbers::pi;
}

}  // namespace smokesvd
