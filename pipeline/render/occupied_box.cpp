#include "pipeline/render/occupied_box.h"

#include "pipeline/render/view_set.h"
#include "runtime/error.h"

namespace smokesvd::render {

namespace {

int64_t blocksAlong(int64_t voxels) { return (voxels + kOccupiedBlock - 1) / kOccupiedBlock; }

void requireShape(const Tensor& tensor, const Shape& expected, const char* what, const Tensor& volume) {
  if (tensor.shape() != expected)
    throw Error(std::string("occupied box: ") + what + " must be " + toString(expected) + " for a volume " +
                toString(volume.shape()) + ", got " + toString(tensor.shape()));
}

}  // namespace

Shape occupiedBlocksShape(const GridSize& grid) { return {blocksAlong(grid.z), blocksAlong(grid.y), blocksAlong(grid.x)}; }

void occupiedBox(Stream& stream, const Tensor& volume, const Tensor& occupied, const Tensor& box) {
  const GridSize grid = volumeGrid(volume, "occupied box");
  const Shape blocks = occupiedBlocksShape(grid);
  requireShape(occupied, blocks, "the block occupancy", volume);
  requireShape(box, {2, 4}, "the box", volume);
  const auto bx = static_cast<int32_t>(blocks[2]), by = static_cast<int32_t>(blocks[1]), bz = static_cast<int32_t>(blocks[0]);
  struct {
    int32_t width, height, depth, blocksX, blocksY, blocksZ;
  } occupancyPush{static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z), bx, by, bz};
  struct {
    int32_t blocksX, blocksY, blocksZ;
  } boxPush{bx, by, bz};
  stream.dispatchFlat(stream.kernel("render/block_occupancy", {64, 1, 1}), {volume, occupied}, occupancyPush,
                      static_cast<uint64_t>(occupied.numel()));
  stream.dispatch(stream.kernel("render/occupied_box", {64, 1, 1}), {occupied, box}, boxPush, {1, 1, 1});
}

Tensor occupiedBox(Stream& stream, const Tensor& volume) {
  const Tensor occupied(stream.context(), occupiedBlocksShape(volumeGrid(volume, "occupied box")));
  Tensor box(stream.context(), {2, 4});
  occupiedBox(stream, volume, occupied, box);
  return box;
}

}  // namespace smokesvd::render
