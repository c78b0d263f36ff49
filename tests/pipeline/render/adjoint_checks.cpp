#include "tests/pipeline/render/adjoint_checks.h"

#include <gtest/gtest.h>

#include "pipeline/render/lift.h"
#include "tests/harness/compare.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/pipeline/render/reference.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

// The views of a check on `grid` at width x height pixels (height = grid.y for CheckCameras::VoxelRows).
std::vector<Camera> checkCameras(CheckCameras kind, const GridSize& grid, int width, int height) {
  if (kind == CheckCameras::Mixed) return mixedCameras(grid, width, height);
  return orbitCameras({0.0, 37.0, 90.0, 151.0, 214.0}, grid, width, height);
}

}  // namespace

void expectRenderBackwardMatchesFiniteDifferences(Context& context, const render::RenderSettings& s, CheckCameras kind) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  const int width = kind == CheckCameras::Mixed ? 6 : 9;
  const std::vector<Camera> cameras = checkCameras(kind, grid, width, 7);
  std::vector<float> density, upstream;
  const Tensor volume = randomTensor(context, grid.volume(), 21, 0.0f, 1.5f, &density);
  const render::ViewSet views = render::uploadViews(context, cameras);
  EXPECT_EQ(views.raysInVoxelRows, kind == CheckCameras::VoxelRows);
  const Tensor gradImages = randomTensor(context, {views.views, 1, 7, width}, 22, -1.0f, 1.0f, &upstream);
  Tensor images(context, {views.views, 1, 7, width});
  Tensor shadow(context, grid.volume());
  Tensor gradDensity = poisonedTensor(context, volume.shape());
  Stream stream(context);
  if (s.light) render::lightTransmittance(stream, volume, s, shadow);
  render::march(stream, volume, s.light ? &shadow : nullptr, views, s, images);
  render::renderBackward(stream, volume, s.light ? &shadow : nullptr, views, s, images, gradImages, gradDensity);
  stream.submit();
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> x) { return reference::render({x.begin(), x.end()}, grid, cameras, s); },
      toDouble(density), toDouble(upstream));
  EXPECT_TRUE(allClose(gradDensity, expected, {2e-4, 2e-3})) << (s.light ? "lit" : "unlit");
}

void expectLiftBackwardMatchesFiniteDifferences(Context& context, CheckCameras kind) {
  const GridSize grid{.x = 9, .y = 7, .z = 5};
  const int width = 8, height = kind == CheckCameras::Mixed ? 6 : 7;
  const std::vector<Camera> cameras = checkCameras(kind, grid, width, height);
  const render::ViewSet views = render::uploadViews(context, cameras);
  EXPECT_EQ(views.raysInVoxelRows, kind == CheckCameras::VoxelRows);
  std::vector<float> images, upstream;
  randomTensor(context, {views.views, 1, height, width}, 41, -1, 1, &images);
  const Tensor gradLifted =
      randomTensor(context, {views.views, grid.z, grid.y, grid.x}, 42, -1, 1, &upstream);
  Tensor gradImages = poisonedTensor(context, {views.views, 1, height, width});
  Stream stream(context);
  render::liftBackward(stream, gradLifted, views, grid, gradImages);
  stream.submit();
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> v) { return reference::lift({v.begin(), v.end()}, cameras, grid); },
      toDouble(images), toDouble(upstream));
  EXPECT_TRUE(allClose(gradImages, expected, {1e-4, 1e-4}));
}

}  // namespace smokesvd::testing
