#include <gtest/gtest.h>

#include "pipeline/render/corner_quads.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

// Every corner quad of odd-sized volumes against a plain CPU gather, the output poisoned before the run:
// quads[q(b)] = (v[b], v[b + x], v[b + y], v[b + x + y]) for b in [-1, W-1] x [-1, H-1] x [-1, D], 0 outside.
TEST_F(GpuTest, CornerQuadsGatherEachSquaresFourCorners) {
  for (const GridSize grid : {GridSize{.x = 5, .y = 7, .z = 3}, GridSize{.x = 1, .y = 2, .z = 1}}) {
    std::vector<float> values;
    const Tensor volume = randomTensor(context(), grid.volume(), 51, -1.0f, 1.0f, &values);
    const Tensor quads = poisonedTensor(context(), render::cornerQuadsShape(grid));
    Stream stream(context());
    render::cornerQuads(stream, volume, quads);
    stream.submit();
    auto at = [&](int64_t x, int64_t y, int64_t z) {
      const bool inside = x >= 0 && y >= 0 && z >= 0 && x < grid.x && y < grid.y && z < grid.z;
      return inside ? values[static_cast<std::size_t>((z * grid.y + y) * grid.x + x)] : 0.0f;
    };
    std::vector<float> expected;
    for (int64_t z = -1; z <= grid.z; ++z)
      for (int64_t y = -1; y < grid.y; ++y)
        for (int64_t x = -1; x < grid.x; ++x)
          for (const float v : {at(x, y, z), at(x + 1, y, z), at(x, y + 1, z), at(x + 1, y + 1, z)}) expected.push_back(v);
    EXPECT_TRUE(allClose(quads, expected, {0.0, 0.0})) << grid.x << "x" << grid.y << "x" << grid.z;
  }
}

TEST_F(GpuTest, CornerQuadsRejectAnOutputOfAnotherShape) {
  const GridSize grid{.x = 3, .y = 2, .z = 2};
  Stream stream(context());
  EXPECT_THROW(render::cornerQuads(stream, Tensor(context(), grid.volume()), Tensor(context(), {12, 4})), Error);
}

}  // namespace
}  // namespace smokesvd::testing
