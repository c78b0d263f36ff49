#include "pipeline/camera/camera.h"

#include <glm/mat3x4.hpp>
#include <glm/matrix.hpp>
#include <cmath>
#include <numbers>

#include "runtime/error.h"

namespace smokesvd {

Ray Camera::ray(double u, double v) const {
  return {origin + u * originPerU + v * originPerV, glm::normalize(direction + u * directionPerU + v * directionPerV)};
}

std::optional<std::array<double, 2>> Camera::project(const Vec3& point) const {
  const glm::dvec3 abc = projection * glm::dvec4(point, 1.0);
  if (abc.z <= 0) return std::nullopt;
  return std::array<double, 2>{abc.x / abc.z, abc.y / abc.z};
}

Vec3 Camera::forward() const { return ray(0.5 * width, 0.5 * height).direction; }

Camera orbitCamera(double angleDegrees, const GridSize& grid, int width, int height) {
  if (width <= 0 || height <= 0 || grid.x <= 0 || grid.y <= 0 || grid.z <= 0)
    throw Error("orbit camera: image " + std::to_string(width) + "x" + std::to_string(height) + " and grid " +
                std::to_string(grid.z) + "x" + std::to_string(grid.y) + "x" + std::to_string(grid.x) +
                " must all be positive");
  const double a = angleDegrees * std::numbers::pi / 180.0;
  const Vec3 forward = {-std::sin(a), 0.0, std::cos(a)};
  const Vec3 right = {std::cos(a), 0.0, std::sin(a)};
  const Vec3 up = {0.0, 1.0, 0.0};
  const double windowWidth = static_cast<double>(grid.x);
  const double windowHeight = static_cast<double>(grid.y);
  const Vec3 centre = grid.centre();
  const double backOff = glm::length(centre) + 1.0;  // starts every ray outside the volume

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
  camera.projection = glm::transpose(glm::dmat3x4(  // the three rows
      glm::dvec4(su * right, su * (0.5 * windowWidth - glm::dot(centre, right))),
      glm::dvec4(-sv * up, sv * (0.5 * windowHeight + glm::dot(centre, up))), glm::dvec4(0.0, 0.0, 0.0, 1.0)));
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

Camera windowCamera(const Camera& camera, double x0, double y0, double windowWidth, double windowHeight, int width,
                    int height) {
  if (width <= 0 || height <= 0 || !(windowWidth > 0) || !(windowHeight > 0) || !std::isfinite(x0) || !std::isfinite(y0))
    throw Error("window camera: a window of " + std::to_string(windowWidth) + "x" + std::to_string(windowHeight) +
                " pixels at (" + std::to_string(x0) + ", " + std::to_string(y0) + ") resampled to " +
                std::to_string(width) + "x" + std::to_string(height) + ": sizes must be positive and finite");
  const double su = windowWidth / width, sv = windowHeight / height;
  Camera window = camera;
  window.width = width;
  window.height = height;
  window.origin = camera.origin + x0 * camera.originPerU + y0 * camera.originPerV;
  window.originPerU = su * camera.originPerU;
  window.originPerV = sv * camera.originPerV;
  window.direction = camera.direction + x0 * camera.directionPerU + y0 * camera.directionPerV;
  window.directionPerU = su * camera.directionPerU;
  window.directionPerV = sv * camera.directionPerV;
  // (a', b', c) = ((a - x0 c) / su, (b - y0 c) / sv, c): pixel' = (pixel - (x0, y0)) / (su, sv). GLM: [column][row].
  for (int column = 0; column < 4; ++column) {
    const double c = camera.projection[column][2];
    window.projection[column][0] = (camera.projection[column][0] - x0 * c) / su;
    window.projection[column][1] = (camera.projection[column][1] - y0 * c) / sv;
  }
  return window;
}

double orbitAngleOf(const Camera& camera) {
  const Vec3 f = camera.forward();
  return std::atan2(-f.x, f.z) * 180.0 / std::numbers::pi;
}

}  // namespace smokesvd
