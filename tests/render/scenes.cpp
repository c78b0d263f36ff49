#include "tests/render/scenes.h"

namespace smokesvd::testing {

Camera lookAtCamera(const GridSize& grid, const Vec3& eye, int width, int height, double fieldOfViewX) {
  // World = grid coordinates (box scale = grid size, voxel_matrix exchanging x and z back).
  VolumeBox box;
  box.voxelMatrix = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1};
  box.scale = {static_cast<double>(grid.width), static_cast<double>(grid.height), static_cast<double>(grid.depth)};
  const Vec3 forward = normalize(grid.centre() - eye);
  const Vec3 right = normalize(cross(forward, {0, 1, 0}));
  const Vec3 up = cross(right, forward);
  CalibratedView view;
  view.fileName = "synthetic";
  view.cameraAngleX = fieldOfViewX;
  view.width = width;
  view.height = height;
  view.cameraToWorld = {right[0], up[0], -forward[0], eye[0], right[1], up[1], -forward[1], eye[1],
                        right[2], up[2], -forward[2], eye[2], 0, 0, 0, 1};
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
