#include "pipeline/dataset/augment.h"

#include <algorithm>

#include "pipeline/media/image.h"
#include "runtime/error.h"

namespace smokesvd::dataset {

void mirrorCellsX(std::vector<float>& values, const GridSize& g) {
  if (g.x <= 0 || values.size() % static_cast<std::size_t>(g.x) != 0)
    throw Error("mirror: values are not rows of the volume's width");
  values = media::mirroredRows(std::move(values), static_cast<int>(g.x));  // grids are bounded far below 2^31
}

void mirrorMacVelocityX(std::vector<float>& velocity, const GridSize& g) {
  const auto cells = static_cast<std::size_t>(g.cells());
  if (velocity.size() != 3 * cells) throw Error("mirror: a MAC velocity must be [3, D, H, W]");
  const auto w = static_cast<std::size_t>(g.x);
  // x faces: the face at i lies between cells i-1 and i; mirrored it becomes face W-i, negated.
  for (std::size_t row = 0; row < cells; row += w) {
    float* u = velocity.data() + row;
    std::vector<float> faces(u, u + w);
    u[0] = 0.0f;  // mirror of the unstored wall face W
    for (std::size_t i = 1; i < w; ++i) u[i] = -faces[w - i];
  }
  std::vector<float> others(velocity.begin() + static_cast<std::ptrdiff_t>(cells), velocity.end());
  mirrorCellsX(others, g);
  std::copy(others.begin(), others.end(), velocity.begin() + static_cast<std::ptrdiff_t>(cells));
}

void mirrorLookX(render::RenderSettings& look) {
  if (look.light) look.light->direction[0] = -look.light->direction[0];
}

void scaleValues(std::vector<float>& values, float factor) {
  for (float& v : values) v *= factor;
}

}  // namespace smokesvd::dataset
