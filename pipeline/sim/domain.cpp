#include "pipeline/sim/domain.h"

#include <algorithm>
#include <cmath>

namespace smokesvd::sim {

physics::GridSize sceneGrid(const Scene& scene) {
  return {scene.resolution[0], scene.resolution[1], scene.resolution[2]};
}

double signedDistance(const Geometry& shape, const Vec3& p) {
  const Vec3 d{p[0] - shape.centre[0], p[1] - shape.centre[1], p[2] - shape.centre[2]};
  auto length = [](double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); };
  switch (shape.kind) {
    case physics::SourceShape::Sphere:
      return length(d[0], d[1], d[2]) - shape.size[0];
    case physics::SourceShape::Box: {
      Vec3 q;
      for (int a = 0; a < 3; ++a) q[a] = std::abs(d[a]) - shape.size[a];
      return length(std::max(q[0], 0.0), std::max(q[1], 0.0), std::max(q[2], 0.0)) +
             std::min(std::max({q[0], q[1], q[2]}), 0.0);
    }
    case physics::SourceShape::Cylinder: {
      const double n = length(shape.axis[0], shape.axis[1], shape.axis[2]);
      const Vec3 axis{shape.axis[0] / n, shape.axis[1] / n, shape.axis[2] / n};
      const double along = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
      const double radial = length(d[0] - along * axis[0], d[1] - along * axis[1], d[2] - along * axis[2]);
      const double qx = radial - shape.size[0], qy = std::abs(along) - shape.size[1];
      return std::hypot(std::max(qx, 0.0), std::max(qy, 0.0)) + std::min(std::max(qx, qy), 0.0);
    }
  }
  return 0;
}

std::vector<float> sceneFlags(const Scene& scene, int frame) {
  const physics::GridSize grid = sceneGrid(scene);
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
