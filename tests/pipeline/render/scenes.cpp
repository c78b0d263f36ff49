#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {

Camera lookAtCamera(const GridSize& grid, const Vec3& eye, int width, int height, double fieldOfViewX) {
  // World = grid coordinates (box scale = grid size, voxel_matrix exchanging x and z back).
  VolumeBox box;
  box.voxelMatrix = glm::dmat4(0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1);  // symmetric
  box.scale = {static_cast<double>(grid.x), static_cast<double>(grid.y), static_cast<double>(grid.z)};
  const Vec3 forward = glm::normalize(grid.centre() - eye);
  const Vec3 right = glm::normalize(glm::cross(forward, Vec3{0, 1, 0}));
  const Vec3 up = glm::cross(right, forward);
  CalibratedView view;
  view.fileName = "synthetic";
  view.cameraAngleX = fieldOfViewX;
  view.width = width;
  view.height = height;
  view.cameraToWorld = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(-forward, 0), glm::dvec4(eye, 1));
  return calibratedCamera(view, box, grid);
}

std::vector<Camera> mixedCameras(const GridSize& grid, int width, int height) {
  std::vector<Camera> cameras = orbitCameras({0.0, 37.0, 90.0}, grid, width, height);
  const Vec3 c = grid.centre();
  cameras.push_back(lookAtCamera(grid, c + Vec3{-9.0, 4.0, -13.0}, width, height, 0.8));
  return cameras;
}

render::RenderSettings unlitSettings() {
  render::RenderSettings s;
  s.step = 0.8f;
  s.absorption = 0.7f;
  s.ambient = 0.9f;
  return s;
}

render::RenderSettings litSettings() {
  render::RenderSettings s = unlitSettings();
  s.ambient = 0.3f;
  render::DirectionalLight light;
  light.direction = {-0.4, 1.0, -0.7};
  light.intensity = 0.9f;
  light.step = 0.9f;
  light.absorption = 0.6f;
  s.light = light;
  return s;
}

}  // namespace smokesvd::testing
