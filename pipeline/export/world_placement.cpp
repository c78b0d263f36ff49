#include "pipeline/export/world_placement.h"

#include <glm/gtc/matrix_transform.hpp>

#include "pipeline/camera/calibration.h"
#include "runtime/error.h"

namespace smokesvd::exporters {
namespace fs = std::filesystem;

nlohmann::json WorldPlacement::describe() const {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({gridToWorld[0][r], gridToWorld[1][r], gridToWorld[2][r], gridToWorld[3][r]});
  return {{"origin", origin},
          {"up", zUp ? "z" : "y"},
          {"grid_to_world", rows},
          {"grid", "cell (i, j, k) of a [z, y, x] array spans [i, i+1] x [j, j+1] x [k, k+1] in grid coordinates"}};
}

WorldPlacement placementOf(const sim::SavedRun& run, const std::optional<fs::path>& calibration, bool zUp) {
  WorldPlacement placement;
  placement.zUp = zUp;
  const std::optional<fs::path> file = calibration ? calibration : run.calibration;
  const GridSize grid = run.grid();
  if (file) {
    if (!fs::exists(*file))
      throw Error(run.root.string() + ": the box was placed by the calibration " + file->string() +
                  ", which is not there; give its place with --calibration FILE");
    placement.gridToWorld = readCalibration(*file).box.gridToWorld(grid);
    placement.origin = "calibration " + fs::absolute(*file).string();
  } else {
    const double w = static_cast<double>(grid.x);
    placement.gridToWorld = glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 / w)) *
                            glm::translate(glm::dmat4(1.0), -0.5 * glm::dvec3(static_cast<double>(grid.x),
                                                                              static_cast<double>(grid.y),
                                                                              static_cast<double>(grid.z)));
    placement.origin = "unit box: 1 world unit wide along x, centred at the origin";
  }
  if (zUp) {
    // (x, y, z) -> (x, -z, y): columns of the rotation.
    const glm::dmat4 toZUp(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, 0, 1));
    placement.gridToWorld = toZUp * placement.gridToWorld;
  }
  return placement;
}

}  // namespace smokesvd::exporters
