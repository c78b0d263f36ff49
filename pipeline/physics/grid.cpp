#include "pipeline/physics/grid.h"

#include <array>
#include <string>
#include <utility>

#include "runtime/error.h"

namespace smokesvd::physics {
namespace {

constexpr int64_t kMinSide = 3;  // one interior cell between two wall layers

GridSize checkedGrid(int64_t z, int64_t y, int64_t x, const Tensor& tensor, const char* what) {
  if (x < kMinSide || y < kMinSide || z < kMinSide)
    throw Error(std::string(what) + ": every side of the grid must be at least " + std::to_string(kMinSide) +
                " cells, got " + toString(tensor.shape()));
  return {.x = x, .y = y, .z = z};
}

// The shape without a leading batch axis of 1.
Shape unbatched(const Tensor& tensor, int rank) {
  Shape shape = tensor.shape();
  if (static_cast<int>(shape.size()) == rank + 1 && shape[0] == 1) shape.erase(shape.begin());
  return shape;
}

}  // namespace

GridSize volumeGrid(const Tensor& volume, const char* what) {
  const Shape shape = unbatched(volume, 3);
  if (shape.size() != 3)
    throw Error(std::string(what) + ": expected a volume [D, H, W], got " + toString(volume.shape()));
  return checkedGrid(shape[0], shape[1], shape[2], volume, what);
}

GridSize vectorGrid(const Tensor& vectorField, const char* what) {
  const Shape shape = unbatched(vectorField, 4);
  if (shape.size() != 4 || shape[0] != 3)
    throw Error(std::string(what) + ": expected a planar vector field [3, D, H, W], got " +
                toString(vectorField.shape()));
  return checkedGrid(shape[1], shape[2], shape[3], vectorField, what);
}

void requireVolume(const Tensor& tensor, const GridSize& grid, const char* what) {
  if (volumeGrid(tensor, what) != grid)
    throw Error(std::string(what) + ": expected a volume " + toString(grid.volume()) + ", got " +
                toString(tensor.shape()));
}

void requireVector(const Tensor& tensor, const GridSize& grid, const char* what) {
  if (vectorGrid(tensor, what) != grid)
    throw Error(std::string(what) + ": expected a vector field " + toString(grid.vector()) + ", got " +
                toString(tensor.shape()));
}

FlagGrid::FlagGrid(Stream& stream, Tensor flags)
    : size_(volumeGrid(flags, "flag grid")), flags_(std::move(flags)), masks_(stream.context(), size_.volume()) {
  struct {
    int32_t nx, ny, nz;
  } push{static_cast<int32_t>(size_.x), static_cast<int32_t>(size_.y), static_cast<int32_t>(size_.z)};
  const std::array<uint32_t, 3> workgroup{16, 4, 1};
  stream.dispatch(stream.kernel("physics/advect_masks", workgroup), {flags_, masks_}, push,
                  {static_cast<uint32_t>((size_.x + 15) / 16), static_cast<uint32_t>((size_.y + 3) / 4),
                   static_cast<uint32_t>(size_.z)});
}

std::vector<float> closedBoxFlags(const GridSize& grid, int wallWidth) {
  std::vector<float> flags(static_cast<std::size_t>(grid.cells()));
  auto wall = [wallWidth](int64_t i, int64_t n) { return i < wallWidth || i >= n - wallWidth; };
  std::size_t index = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i)
        flags[index++] = static_cast<float>(wall(i, grid.x) || wall(j, grid.y) || wall(k, grid.z) ? kObstacle : kFluid);
  return flags;
}

Tensor closedBoxFlagsTensor(Context& context, const GridSize& grid, int wallWidth) {
  return Tensor::fromHost(context, grid.volume(), closedBoxFlags(grid, wallWidth));
}

namespace {

void convertLayout(Stream& stream, const Tensor& from, const Tensor& to, int32_t toPlanar) {
  const uint32_t cells = static_cast<uint32_t>(from.numel() / 3);
  struct {
    uint32_t cells;
  } push{cells};
  const Kernel& kernel = stream.kernel("physics/velocity_layout", {64, 1, 1}, {toPlanar});
  stream.dispatchFlat(kernel, {from, to}, push, cells);
}

void requireInterleaved(const Tensor& interleaved, const GridSize& grid) {
  Shape shape = interleaved.shape();
  if (shape.size() == 5 && shape[0] == 1) shape.erase(shape.begin());
  if (shape != Shape{grid.z, grid.y, grid.x, 3})
    throw Error("velocity layout: expected an interleaved field [" + std::to_string(grid.z) + ", " +
                std::to_string(grid.y) + ", " + std::to_string(grid.x) + ", 3], got " + toString(interleaved.shape()));
}

}  // namespace

void interleavedToPlanar(Stream& stream, const Tensor& interleaved, const Tensor& planar) {
  requireInterleaved(interleaved, vectorGrid(planar, "velocity layout (planar)"));
  convertLayout(stream, interleaved, planar, 1);
}

void planarToInterleaved(Stream& stream, const Tensor& planar, const Tensor& interleaved) {
  requireInterleaved(interleaved, vectorGrid(planar, "velocity layout (planar)"));
  convertLayout(stream, planar, interleaved, 0);
}

}  // namespace smokesvd::physics
