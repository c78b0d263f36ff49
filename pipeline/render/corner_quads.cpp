#include "pipeline/render/corner_quads.h"

#include "pipeline/render/view_set.h"
#include "runtime/error.h"

namespace smokesvd::render {

Shape cornerQuadsShape(const GridSize& grid) { return {(grid.x + 1) * (grid.y + 1) * (grid.z + 2), 4}; }

void cornerQuads(Stream& stream, const Tensor& volume, const Tensor& quads) {
  const GridSize grid = volumeGrid(volume, "corner quads");
  if (quads.shape() != cornerQuadsShape(grid))
    throw Error("corner quads: the output must be " + toString(cornerQuadsShape(grid)) + " for a volume " +
                toString(volume.shape()) + ", got " + toString(quads.shape()));
  struct {
    int32_t width, height, depth;
  } push{static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
  stream.dispatchFlat(stream.kernel("render/corner_quads", {64, 1, 1}), {volume, quads}, push,
                      static_cast<uint64_t>(quads.size(0)));
}

Tensor cornerQuads(Stream& stream, const Tensor& volume) {
  Tensor quads(stream.context(), cornerQuadsShape(volumeGrid(volume, "corner quads")));
  cornerQuads(stream, volume, quads);
  return quads;
}

}  // namespace smokesvd::render
