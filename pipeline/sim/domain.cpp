#include "pipeline/sim/domain.h"

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>

namespace smokesvd::sim {

double signedDistance(const Geometry& shape, const Vec3& p) {
  const Vec3 d = p - shape.centre;
  switch (shape.kind) {
    case physics::SourceShape::Sphere:
      return glm::length(d) - shape.size.x;
    case physics::SourceShape::Box: {
      const Vec3 q = glm::abs(d) - shape.size;
      return glm::length(glm::max(q, 0.0)) + std::min(std::max({q.x, q.y, q.z}), 0.0);
    }
    case physics::SourceShape::Cylinder: {
      const Vec3 axis = shape.axis / glm::length(shape.axis);
      const double along = glm::dot(d, axis);
      const double radial = glm::length(d - along * axis);
      const double qx = radial - shape.size.x, qy = std::abs(along) - shape.size.y;
      return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0);
    }
  }
  return 0;
}

std::vector<float> sceneFlags(const Scene& scene, int frame) {
  const GridSize& grid = scene.resolution;
  std::vector<float> flags(static_cast<std::size_t>(grid.cells()));
  const int64_t sides[3] = {grid.x, grid.y, grid.z};
  std::size_t index = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i, ++index) {
        const int64_t c[3] = {i, j, k};
        bool wall = false, open = false;
        for (int a = 0; a < 3; ++a) {
          for (int high = 0; high < 2; ++high) {
            if (c[a] != (high ? sides[a] - 1 : 0)) continue;
            (scene.boundaries[2 * a + high] == Boundary::Wall ? wall : open) = true;
          }
        }
        bool inside = false;
        const Vec3 centre{static_cast<double>(i) + 0.5, static_cast<double>(j) + 0.5, static_cast<double>(k) + 0.5};
        for (const Obstacle& obstacle : scene.obstacles)
          inside = inside || (obstacle.frames.contains(frame) && signedDistance(obstacle.shape, centre) <= 0);
        flags[index] = wall || inside ? static_cast<float>(physics::kObstacle)
                                      : static_cast<float>(open ? physics::kEmpty : physics::kFluid);
      }
  return flags;
}

bool obstaclesChangeAt(const Scene& scene, int frame) {
  if (frame == 0) return false;
  return std::any_of(scene.obstacles.begin(), scene.obstacles.end(), [&](const Obstacle& o) {
    return o.frames.contains(frame) != o.frames.contains(frame - 1);
  });
}

}  // namespace smokesvd::sim
