#include <gtest/gtest.h>

#include "pipeline/render/lift.h"
#include "pipeline/render/renderer.h"
#include "pipeline/render/rotate.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/pipeline/render/adjoint_checks.h"
#include "tests/pipeline/render/reference.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

double dotProduct(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += static_cast<double>(a[i]) * b[i];
  return sum;
}

// Images of 6 rows, and of the grid's 7 rows, where the orbit views' voxel centres fall on rows of pixel centres
// and the lift takes its two-pixel loop (lift.comp); the perspective view takes the general one either way.
TEST_F(GpuTest, LiftMatchesReferenceAndTheAdjointIsItsTranspose) {
  const GridSize grid{.x = 9, .y = 7, .z = 5};
  const int width = 8;
  for (const int height : {6, 7}) {
    const std::vector<Camera> cameras = mixedCameras(grid, width, height);
    const render::ViewSet views = render::uploadViews(context(), cameras);
    const Shape imageShape{views.views, 1, height, width};
    const Shape liftedShape{views.views, grid.z, grid.y, grid.x};
    std::vector<float> images, upstream;
    const Tensor x = randomTensor(context(), imageShape, 41, -1, 1, &images);
    const Tensor y = randomTensor(context(), liftedShape, 42, -1, 1, &upstream);
    Tensor lifted = poisonedTensor(context(), liftedShape);
    Tensor gradImages = poisonedTensor(context(), imageShape);
    Stream stream(context());
    render::lift(stream, x, views, grid, lifted);
    render::liftBackward(stream, y, views, grid, gradImages);
    stream.submit();
    EXPECT_TRUE(allClose(lifted, reference::lift(toDouble(images), cameras, grid), {1e-5, 1e-4})) << height << " rows";
    // <A x, y> = <x, A^T y>
    const double left = dotProduct(lifted.download(), upstream), right = dotProduct(images, gradImages.download());
    EXPECT_NEAR(left, right, 1e-4 * (std::abs(left) + 1)) << height << " rows";
  }
}

TEST_F(GpuTest, LiftBackwardMatchesFiniteDifferences) { expectLiftBackwardMatchesFiniteDifferences(context()); }

// Orbit views with one pixel row per voxel row: on CPU devices by voxel planes, without atomics.
TEST_F(GpuTest, LiftBackwardByVoxelPlanesMatchesFiniteDifferences) {
  expectLiftBackwardMatchesFiniteDifferences(context(), CheckCameras::VoxelRows);
}

TEST_F(GpuTest, FrontLiftBroadcastsTheImageAlongDepth) {
  const GridSize grid{.x = 5, .y = 4, .z = 3};
  std::vector<float> image;
  const Tensor x = randomTensor(context(), {1, 1, 4, 5}, 43, 0, 1, &image);
  const render::ViewSet views = render::uploadViews(context(), orbitCameras({0.0}, grid, 5, 4));
  Tensor lifted = poisonedTensor(context(), {1, 3, 4, 5});
  Stream stream(context());
  render::lift(stream, x, views, grid, lifted);
  stream.submit();
  std::vector<double> expected;
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 4; ++y)
      for (int c = 0; c < 5; ++c) expected.push_back(image[static_cast<std::size_t>((3 - y) * 5 + c)]);
  EXPECT_TRUE(allClose(lifted, expected, {1e-6, 1e-6}));
}

class RotateTest : public GpuTest, public ::testing::WithParamInterface<double> {};

TEST_P(RotateTest, MatchesReferenceAndItsAdjoint) {
  const double angle = GetParam();
  const GridSize grid{.x = 9, .y = 5, .z = 7};
  const Shape shape{2, grid.z, grid.y, grid.x};
  std::vector<float> volume, upstream;
  const Tensor x = randomTensor(context(), shape, 51, -1, 1, &volume);
  const Tensor y = randomTensor(context(), shape, 52, -1, 1, &upstream);
  Tensor rotated = poisonedTensor(context(), shape);
  Tensor gradVolume = poisonedTensor(context(), shape);
  Stream stream(context());
  render::rotate(stream, x, angle, rotated);
  render::rotateBackward(stream, y, angle, gradVolume);
  stream.submit();
  EXPECT_TRUE(allClose(rotated, reference::rotate(toDouble(volume), 2, grid, angle), {1e-5, 1e-5}));
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> v) { return reference::rotate({v.begin(), v.end()}, 2, grid, angle); },
      toDouble(volume), toDouble(upstream));
  EXPECT_TRUE(allClose(gradVolume, expected, {1e-5, 1e-4}));
  const double left = dotProduct(rotated.download(), upstream), right = dotProduct(volume, gradVolume.download());
  EXPECT_NEAR(left, right, 1e-4 * (std::abs(left) + 1));
}

INSTANTIATE_TEST_SUITE_P(Angles, RotateTest, ::testing::Values(0.0, 30.0, 90.0, 137.0, -61.0));

TEST_F(GpuTest, RotatedVolumeSeenFromTheFrontIsTheVolumeSeenFromTheOrbitAngle) {
  const GridSize grid{.x = 7, .y = 5, .z = 7};  // square in x-z, so a quarter turn maps the grid onto itself
  const Shape shape = grid.volume();
  const Tensor volume = randomTensor(context(), shape, 61, 0, 1);
  Tensor rotated(context(), shape);
  const render::ViewSet front = render::uploadViews(context(), orbitCameras({0.0}, grid, 7, 5));
  const render::ViewSet side = render::uploadViews(context(), orbitCameras({90.0}, grid, 7, 5));
  Tensor frontOfRotated(context(), {1, 1, 5, 7});
  Tensor sideOfVolume(context(), {1, 1, 5, 7});
  Stream stream(context());
  render::rotate(stream, volume, 90.0, rotated);
  render::render(stream, rotated, front, unlitSettings(), frontOfRotated);
  render::render(stream, volume, side, unlitSettings(), sideOfVolume);
  stream.submit();
  EXPECT_TRUE(allClose(frontOfRotated, sideOfVolume.download(), {1e-5, 1e-4}));
}

TEST_F(GpuTest, LiftAndRotateRejectBadShapes) {
  const GridSize grid{.x = 5, .y = 4, .z = 3};
  const render::ViewSet views = render::uploadViews(context(), orbitCameras({0.0, 90.0}, grid, 5, 4));
  Stream stream(context());
  EXPECT_THROW(render::lift(stream, Tensor(context(), {1, 1, 4, 5}), views, grid, Tensor(context(), {2, 3, 4, 5})),
               Error);
  EXPECT_THROW(render::lift(stream, Tensor(context(), {2, 1, 4, 5}), views, grid, Tensor(context(), {2, 3, 4, 4})),
               Error);
  EXPECT_THROW(render::rotate(stream, Tensor(context(), {3, 4, 5}), 10.0, Tensor(context(), {3, 4, 4})), Error);
}

}  // namespace
}  // namespace smokesvd::testing
