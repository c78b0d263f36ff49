#include "pipeline/differentiable/example_draws.h"

#include <random>

#include "pipeline/physics/grid.h"

namespace smokesvd::diff {

InputDraw flagsDraw(Shape shape, float obstacles, float empty) {
  return {std::move(shape),
          [obstacles, empty](const Shape& s, uint64_t seed) {
            std::vector<float> flags = physics::closedBoxFlags(GridSize{.x = s[2], .y = s[1], .z = s[0]});
            std::mt19937_64 generator(seed);
            std::uniform_real_distribution<float> kind(0, 1);
            for (float& flag : flags) {
              const float k = kind(generator);
              if (flag != static_cast<float>(physics::kFluid)) continue;
              if (k < obstacles) flag = static_cast<float>(physics::kObstacle);
              else if (k < obstacles + empty) flag = static_cast<float>(physics::kEmpty);
            }
            return flags;
          },
          false};
}

}  // namespace smokesvd::diff
