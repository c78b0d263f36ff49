#include "pipeline/export/nerf_cameras.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "runtime/error.h"

namespace smokesvd::exporters {
namespace {

constexpr int kLattice = 9;

struct ViewFrame {
  glm::dvec3 centre;             // on the central ray, nearest the box centre (world)
  glm::dvec3 right, down, forward;  // unit vectors (world)
  double pixelWidth = 0, pixelHeight = 0;  // world length of one pixel along u and v
};

ViewFrame viewFrame(const Camera& view, const GridSize& grid, const WorldPlacement& placement) {
  if (view.perspective) throw Error("export --nerf: the run's views are perspective; only orbit views are exported");
  const glm::dmat4& G = placement.gridToWorld;
  const glm::dmat3 L = placement.linear();
  ViewFrame f;
  const glm::dvec3 r = L * view.originPerU, d = L * view.originPerV;
  f.pixelWidth = glm::length(r);
  f.pixelHeight = glm::length(d);
  f.right = r / f.pixelWidth;
  f.down = d / f.pixelHeight;
  f.forward = glm::normalize(L * view.direction);
  if (std::abs(glm::dot(f.right, f.forward)) > 1e-9 || std::abs(glm::dot(f.down, f.forward)) > 1e-9 ||
      std::abs(glm::dot(f.right, f.down)) > 1e-9)
    throw Error("export --nerf: in this run's world the orbit views are oblique (voxels that are not square in the "
                "horizontal plane); they have no pinhole equivalent");
  const Vec3 gridCentre = view.origin + 0.5 * view.width * view.originPerU + 0.5 * view.height * view.originPerV;
  const glm::dvec3 rayPoint = glm::dvec3(G * glm::dvec4(gridCentre, 1.0));
  const glm::dvec3 boxCentre = glm::dvec3(G * glm::dvec4(0.5 * static_cast<double>(grid.x), 0.5 * static_cast<double>(grid.y),
                                                         0.5 * static_cast<double>(grid.z), 1.0));
  f.centre = rayPoint + glm::dot(boxCentre - rayPoint, f.forward) * f.forward;
  return f;
}

}  // namespace

glm::dvec2 projectPinhole(const PinholeCamera& camera, const glm::dvec3& world) {
  const glm::dmat4& c = camera.cameraToWorld;
  const glm::dvec3 right(c[0]), up(c[1]), back(c[2]), position(c[3]);
  const glm::dvec3 rel = world - position;
  const double depth = -glm::dot(rel, back);
  return {camera.cx + camera.fx * glm::dot(rel, right) / depth, camera.cy - camera.fy * glm::dot(rel, up) / depth};
}

PinholeApproximation pinholeCameras(const std::vector<Camera>& views, const GridSize& grid, const WorldPlacement& placement,
                                    double maxErrorPixels) {
  if (!(maxErrorPixels > 0)) throw Error("export --nerf: the camera error must be > 0 pixels");
  std::vector<ViewFrame> frames;
  for (const Camera& view : views) frames.push_back(viewFrame(view, grid, placement));
  std::vector<glm::dvec3> lattice;
  for (int k = 0; k < kLattice; ++k)
    for (int j = 0; j < kLattice; ++j)
      for (int i = 0; i < kLattice; ++i) {
        const glm::dvec4 p(static_cast<double>(grid.x) * i / (kLattice - 1), static_cast<double>(grid.y) * j / (kLattice - 1),
                           static_cast<double>(grid.z) * k / (kLattice - 1), 1.0);
        lattice.push_back(glm::dvec3(placement.gridToWorld * p));
      }
  // error = s |d| / (D + d) <= e  <=>  D >= s |d| / e - d, with s the orthographic offset in pixels.
  PinholeApproximation result;
  double deepest = 0;
  for (const ViewFrame& f : frames)
    for (const glm::dvec3& x : lattice) {
      const glm::dvec3 rel = x - f.centre;
      const double d = glm::dot(rel, f.forward);
      const double s = std::hypot(glm::dot(rel, f.right) / f.pixelWidth, glm::dot(rel, f.down) / f.pixelHeight);
      deepest = std::max(deepest, std::abs(d));
      result.distance = std::max(result.distance, s * std::abs(d) / maxErrorPixels - d);
    }
  result.distance = std::max(result.distance, 2 * deepest);
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ViewFrame& f = frames[v];
    PinholeCamera camera;
    camera.width = views[v].width;
    camera.height = views[v].height;
    camera.fx = result.distance / f.pixelWidth;
    camera.fy = result.distance / f.pixelHeight;
    camera.cx = 0.5 * camera.width;
    camera.cy = 0.5 * camera.height;
    camera.cameraToWorld = glm::dmat4(glm::dvec4(f.right, 0), glm::dvec4(-f.down, 0), glm::dvec4(-f.forward, 0),
                                      glm::dvec4(f.centre - result.distance * f.forward, 1));
    result.squarePixels = result.squarePixels && std::abs(camera.fx - camera.fy) <= 1e-9 * camera.fx;
    for (const glm::dvec3& x : lattice) {
      const glm::dvec3 rel = x - f.centre;
      const glm::dvec2 orthographic(camera.cx + glm::dot(rel, f.right) / f.pixelWidth, camera.cy + glm::dot(rel, f.down) / f.pixelHeight);
      result.maxErrorPixels = std::max(result.maxErrorPixels, glm::length(projectPinhole(camera, x) - orthographic));
    }
    result.cameras.push_back(camera);
  }
  return result;
}

}  // namespace smokesvd::exporters
