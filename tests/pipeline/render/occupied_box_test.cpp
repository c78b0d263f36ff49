#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "pipeline/render/occupied_box.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

// A volume of `grid` that is zero but for the voxels `nonzero` picks (index -> whether it holds a value).
template <typename Pick>
std::vector<float> sparseValues(const GridSize& grid, uint64_t seed, Pick nonzero) {
  std::vector<float> values = randomValues(static_cast<std::size_t>(grid.x * grid.y * grid.z), seed, -1.0f, 1.0f);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!nonzero(static_cast<int64_t>(i))) values[i] = (i % 3 == 0) ? -0.0f : 0.0f;
  return values;
}

struct Expected {
  std::vector<float> occupied;
  std::array<float, 8> box;
};

// The plain scan: block k occupied when one of its voxels, [4k, 4k + 3] (each axis, inside the grid), is non-zero;
// the box low = 4 min k - 1/2, high = 4 (max k + 1) + 1/2 over them, or 1e30 / -1e30 where none is.
Expected reference(const std::vector<float>& values, const GridSize& grid) {
  const Shape blocks = render::occupiedBlocksShape(grid);
  Expected e;
  std::array<int64_t, 3> low{blocks[2], blocks[1], blocks[0]}, high{-1, -1, -1};
  for (int64_t bz = 0; bz < blocks[0]; ++bz)
    for (int64_t by = 0; by < blocks[1]; ++by)
      for (int64_t bx = 0; bx < blocks[2]; ++bx) {
        bool occupied = false;
        for (int64_t z = 4 * bz; z <= std::min(4 * bz + 3, grid.z - 1); ++z)
          for (int64_t y = 4 * by; y <= std::min(4 * by + 3, grid.y - 1); ++y)
            for (int64_t x = 4 * bx; x <= std::min(4 * bx + 3, grid.x - 1); ++x)
              occupied = occupied || values[static_cast<std::size_t>((z * grid.y + y) * grid.x + x)] != 0.0f;
        e.occupied.push_back(occupied ? 1.0f : 0.0f);
        if (!occupied) continue;
        const std::array<int64_t, 3> block{bx, by, bz};
        for (int a = 0; a < 3; ++a) {
          low[a] = std::min(low[a], block[a]);
          high[a] = std::max(high[a], block[a]);
        }
      }
  if (high[0] < 0) {
    e.box = {1e30f, 1e30f, 1e30f, 1e30f, -1e30f, -1e30f, -1e30f, -1e30f};
  } else {
    for (int a = 0; a < 3; ++a) {
      e.box[a] = 4.0f * static_cast<float>(low[a]) - 0.5f;
      e.box[4 + a] = 4.0f * static_cast<float>(high[a] + 1) + 0.5f;
    }
    e.box[3] = e.box[7] = 0.0f;
  }
  return e;
}

// Every block's occupancy and the box of odd-sized volumes (and ones of whole blocks) against the plain scan,
// the outputs poisoned before the run: one non-zero voxel at the first or the last voxel, a few scattered
// ones, a blob, everything, nothing (with negative zeros, which are zeros).
TEST_F(GpuTest, OccupiedBoxMatchesAPlainScanOfTheBlocks) {
  for (const GridSize grid : {GridSize{.x = 9, .y = 13, .z = 7}, GridSize{.x = 8, .y = 12, .z = 4},
                              GridSize{.x = 1, .y = 2, .z = 1}, GridSize{.x = 17, .y = 5, .z = 6}}) {
    const int64_t voxels = grid.x * grid.y * grid.z;
    const std::vector<std::vector<float>> volumes{
        sparseValues(grid, 61, [](int64_t i) { return i == 0; }),
        sparseValues(grid, 62, [&](int64_t i) { return i == voxels - 1; }),
        sparseValues(grid, 63, [](int64_t i) { return i % 97 == 41; }),
        sparseValues(grid, 64,
                     [&](int64_t i) {
                       const int64_t x = i % grid.x, y = (i / grid.x) % grid.y, z = i / (grid.x * grid.y);
                       return x >= grid.x / 3 && x <= grid.x / 2 && y >= grid.y / 2 && z <= grid.z / 2;
                     }),
        sparseValues(grid, 65, [](int64_t) { return true; }),
        sparseValues(grid, 66, [](int64_t) { return false; }),
    };
    for (std::size_t v = 0; v < volumes.size(); ++v) {
      const Tensor volume = Tensor::fromHost(context(), grid.volume(), volumes[v]);
      const Tensor occupied = poisonedTensor(context(), render::occupiedBlocksShape(grid));
      const Tensor box = poisonedTensor(context(), {2, 4});
      Stream stream(context());
      render::occupiedBox(stream, volume, occupied, box);
      stream.submit();
      const Expected e = reference(volumes[v], grid);
      const std::string where = std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" + std::to_string(grid.z) +
                                ", volume " + std::to_string(v);
      EXPECT_TRUE(allClose(occupied, e.occupied, {0.0, 0.0})) << where;
      EXPECT_TRUE(allClose(box, std::vector<float>(e.box.begin(), e.box.end()), {0.0, 0.0})) << where;
    }
  }
}

TEST_F(GpuTest, OccupiedBoxRejectsOutputsOfAnotherShape) {
  const GridSize grid{.x = 9, .y = 5, .z = 4};
  const Tensor volume(context(), grid.volume());
  Stream stream(context());
  EXPECT_THROW(render::occupiedBox(stream, volume, Tensor(context(), {2, 2, 2}), Tensor(context(), {2, 4})), Error);
  EXPECT_THROW(render::occupiedBox(stream, volume, Tensor(context(), {1, 2, 3}), Tensor(context(), {8})), Error);
}

}  // namespace
}  // namespace smokesvd::testing
