#include <gtest/gtest.h>

#include "pipeline/render/atomics.h"
#include "pipeline/render/lift.h"
#include "pipeline/render/occupied_box.h"
#include "pipeline/render/renderer.h"
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

struct Scene {
  GridSize grid;
  int width, height;
};

// The lift's side of an adjoint run: views of `grid`, the upstream gradient of the lifted volumes, and the
// shape of the image gradient.
struct LiftCase {
  const render::ViewSet& views;
  GridSize grid;
  const Tensor& gradLifted;
  Shape imageShape;
};

struct AdjointGradients {
  std::vector<float> density, images;  // the render's density gradient, the lift's image gradient
};

// Renders `volume` through `views` with `s` and runs both adjoints, their outputs poisoned first; with
// `scattered` under SMOKESVD_FAST_SCATTER=1 (one ray or lifted value per invocation, float atomics).
AdjointGradients runAdjoints(Context& context, const Tensor& volume, const render::ViewSet& views,
                             const render::RenderSettings& s, const Tensor& gradImages, const LiftCase& lift,
                             bool scattered) {
  if (scattered) setenv("SMOKESVD_FAST_SCATTER", "1", 1);
  const Tensor images(context, gradImages.shape()), shadow(context, volume.shape());
  const Tensor grad = poisonedTensor(context, volume.shape()), gradOfLift = poisonedTensor(context, lift.imageShape);
  Stream stream(context);
  if (s.light) render::lightTransmittance(stream, volume, s, shadow);
  render::march(stream, volume, s.light ? &shadow : nullptr, views, s, images);
  render::renderBackward(stream, volume, s.light ? &shadow : nullptr, views, s, images, gradImages, grad);
  render::liftBackward(stream, lift.gradLifted, lift.views, lift.grid, gradOfLift);
  stream.submit();
  unsetenv("SMOKESVD_FAST_SCATTER");
  return {grad.download(), gradOfLift.download()};
}

class RendererTest : public GpuTest, public ::testing::WithParamInterface<bool> {
 protected:
  render::RenderSettings settings() const { return GetParam() ? litSettings() : unlitSettings(); }
};

TEST_P(RendererTest, ForwardMatchesReference) {
  for (const Scene& scene : {Scene{{.x = 6, .y = 7, .z = 5}, 6, 7}, Scene{{.x = 7, .y = 11, .z = 9}, 5, 9}}) {
    const std::vector<Camera> cameras = mixedCameras(scene.grid, scene.width, scene.height);
    std::vector<float> density;
    const Tensor volume = randomTensor(context(), scene.grid.volume(), 11, 0.0f,
                                       1.5f, &density);
    const render::ViewSet views = render::uploadViews(context(), cameras);
    Tensor images = poisonedTensor(context(), {views.views, 1, scene.height, scene.width});
    Stream stream(context());
    render::render(stream, volume, views, settings(), images);
    stream.submit();
    const std::vector<double> expected = reference::render(toDouble(density), scene.grid, cameras, settings());
    EXPECT_TRUE(allClose(images, expected, {2e-5, 2e-4}));
  }
}

TEST_P(RendererTest, BackwardMatchesFiniteDifferences) {
  expectRenderBackwardMatchesFiniteDifferences(context(), settings());
}

// Orbit views with one pixel row per voxel row: on CPU devices by voxel planes, without atomics.
TEST_P(RendererTest, BackwardByVoxelPlanesMatchesFiniteDifferences) {
  expectRenderBackwardMatchesFiniteDifferences(context(), settings(), CheckCameras::VoxelRows);
}

// The adjoints by voxel planes (views in voxel rows, CPU devices) give the scattered adjoints' gradients
// (SMOKESVD_FAST_SCATTER=1: one invocation per ray or lifted value, float atomics) up to the order of the
// additions, on odd sizes with the views at every angle.
TEST_P(RendererTest, AdjointsByVoxelPlanesMatchTheScatteredOnes) {
  if (!render::deterministicScatter(context())) GTEST_SKIP() << "the adjoints by voxel planes run on CPU devices";
  const GridSize grid{.x = 13, .y = 9, .z = 11};
  const render::ViewSet views = render::uploadViews(context(), orbitCameras(orbitAngles(7), grid, 15, 9));
  ASSERT_TRUE(views.raysInVoxelRows);
  const Tensor volume = randomTensor(context(), grid.volume(), 31, 0.0f, 1.5f);
  const Tensor gradImages = randomTensor(context(), {7, 1, 9, 15}, 32);
  const Tensor gradLifted = randomTensor(context(), {7, 11, 9, 13}, 33);
  const LiftCase lift{views, grid, gradLifted, gradImages.shape()};
  const AdjointGradients planes = runAdjoints(context(), volume, views, settings(), gradImages, lift, false);
  const AdjointGradients scattered = runAdjoints(context(), volume, views, settings(), gradImages, lift, true);
  EXPECT_TRUE(allClose(planes.density, scattered.density, volume.shape(), {1e-5, 1e-5}));
  EXPECT_TRUE(allClose(planes.images, scattered.images, gradImages.shape(), {1e-5, 1e-5}));
}

// One recording with a device look renders, after each upload of another look, exactly what a fresh
// recording with those settings renders; its backward pass follows the uploaded look too.
TEST_F(GpuTest, ADeviceLookChangesTheRenderOfOneRecording) {
  const GridSize grid{.x = 6, .y = 9, .z = 7};
  const std::vector<Camera> cameras = mixedCameras(grid, 6, 9);
  const render::ViewSet views = render::uploadViews(context(), cameras);
  const Tensor volume = randomTensor(context(), {7, 9, 6}, 3, 0.0f, 1.5f);
  const Tensor gradImages = randomTensor(context(), {views.views, 1, 9, 6}, 4);
  render::RenderSettings recorded = litSettings();
  recorded.look = render::lookTensor(context(), recorded);
  const Tensor images(context(), {views.views, 1, 9, 6}), shadow(context(), {7, 9, 6}), grad(context(), {7, 9, 6});
  Stream stream(context());
  render::lightTransmittance(stream, volume, recorded, shadow);
  render::march(stream, volume, &shadow, views, recorded, images);
  render::renderBackward(stream, volume, &shadow, views, recorded, images, gradImages, grad);

  render::RenderSettings other = litSettings();
  other.absorption *= 1.7f;
  other.ambient = 0.2f;
  other.light->intensity = 0.4f;
  other.light->absorption = 0.6f;
  other.light->direction = {0.8, 0.3, -0.2};
  for (const render::RenderSettings& look : {other, litSettings()}) {
    render::uploadLook(recorded.look, look);
    stream.submit();
    const Tensor fresh(context(), images.shape()), freshShadow(context(), shadow.shape()), freshGrad(context(), grad.shape());
    Stream check(context());
    render::lightTransmittance(check, volume, look, freshShadow);
    render::march(check, volume, &freshShadow, views, look, fresh);
    render::renderBackward(check, volume, &freshShadow, views, look, fresh, gradImages, freshGrad);
    check.submit();
    EXPECT_TRUE(allClose(images, fresh.download(), {0, 0}));
    EXPECT_TRUE(allClose(grad, freshGrad.download(), {1e-6, 1e-5}));  // atomics: summation order
  }
  EXPECT_EQ(render::lookValues(other)[1], 0.2f);
  EXPECT_THROW(render::uploadLook(Tensor(context(), {7}), other), Error);
}

// On CPU devices the scattering adjoints run in a fixed order: the same gradient bit for bit, run after run.
TEST_F(GpuTest, RenderAndLiftAdjointsAreDeterministicOnCpuDevices) {
  if (!render::deterministicScatter(context())) GTEST_SKIP() << "this device scatters in any order";
  const GridSize grid{.x = 7, .y = 11, .z = 9};
  const render::ViewSet views = render::uploadViews(context(), mixedCameras(grid, 7, 11));
  const Tensor volume = randomTensor(context(), grid.volume(), 5, 0.0f, 1.5f);
  const Tensor gradImages = randomTensor(context(), {views.views, 1, 11, 7}, 6);
  const Tensor gradLifted = randomTensor(context(), {views.views, 9, 11, 7}, 7);
  std::vector<AdjointGradients> runs;
  for (int run = 0; run < 3; ++run)
    runs.push_back(runAdjoints(context(), volume, views, litSettings(), gradImages,
                               {views, grid, gradLifted, gradImages.shape()}, false));
  for (int run = 1; run < 3; ++run) {
    EXPECT_EQ(runs[0].density, runs[static_cast<std::size_t>(run)].density);
    EXPECT_EQ(runs[0].images, runs[static_cast<std::size_t>(run)].images);
  }
}

// llvmpipe ends the loops of one invocation after 65535 iterations in all: the deterministic adjoints must
// spread their work so that no invocation passes it. The scatters spread rays and lifted values over
// shards: one workgroup would run 250,000 march steps (views of 20 rows, not the volume's 40) and 82,000
// lift values (views of 8 rows) per invocation. The adjoints by voxel planes (views in voxel rows) split the
// views over dispatches: one invocation would run 16 views of 24 rays of 700 steps, and 16 views of 64 x 64
// lift values. The gradients must equal those of the wide dispatch (one ray or value per invocation) up
// to the order of the additions.
TEST_F(GpuTest, DeterministicAdjointsPassTheLoopLimitOfCpuDevices) {
  if (!render::deterministicScatter(context())) GTEST_SKIP() << "this device scatters in any order";
  const GridSize grid{.x = 24, .y = 40, .z = 24}, liftGrid{.x = 64, .y = 80, .z = 64};
  const Tensor volume = randomTensor(context(), grid.volume(), 8, 0.0f, 0.05f);
  const Tensor gradLifted = randomTensor(context(), {16, 64, 80, 64}, 10);
  render::RenderSettings s = litSettings();
  s.step = 0.05f;
  for (const int rows : {40, 20}) {
    const render::ViewSet views = render::uploadViews(context(), orbitCameras(orbitAngles(16), grid, 24, rows));
    const int liftRows = rows == 40 ? 80 : 8;
    const render::ViewSet liftViews = render::uploadViews(context(), orbitCameras(orbitAngles(16), liftGrid, 64, liftRows));
    ASSERT_EQ(views.raysInVoxelRows, rows == 40);
    ASSERT_EQ(liftViews.raysInVoxelRows, rows == 40);
    const Tensor gradImages = randomTensor(context(), {16, 1, rows, 24}, 9);
    const LiftCase lift{liftViews, liftGrid, gradLifted, {16, 1, liftRows, 64}};
    const AdjointGradients deterministic = runAdjoints(context(), volume, views, s, gradImages, lift, false);
    const AdjointGradients wide = runAdjoints(context(), volume, views, s, gradImages, lift, true);
    EXPECT_TRUE(allClose(deterministic.density, wide.density, volume.shape(), {1e-5, 1e-4})) << rows << " rows";
    // Up to 64 x 64 x 80 / (64 x 8) = 640 terms a pixel with 8 rows.
    EXPECT_TRUE(allClose(deterministic.images, wide.images, lift.imageShape, {1e-4, 1e-4})) << rows << " rows";
  }
}

// A recording chooses its adjoint kernels by whether the views' rays run in voxel rows, so the cameras
// rewritten into a view set must keep that.
TEST_F(GpuTest, RewrittenViewsKeepWhetherTheirRaysRunInVoxelRows) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  const render::ViewSet rows = render::uploadViews(context(), orbitCameras({0.0, 90.0}, grid, 6, 7));
  EXPECT_TRUE(rows.raysInVoxelRows);
  render::rewriteViews(rows, orbitCameras({11.25, 33.75}, grid, 6, 7));
  const std::vector<Camera> perspective{lookAtCamera(grid, grid.centre() + Vec3{-9.0, 4.0, -13.0}, 6, 7, 0.8),
                                        orbitCameras({0.0}, grid, 6, 7)[0]};
  try {
    render::rewriteViews(rows, perspective);
    ADD_FAILURE() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("rows of voxel centres"), std::string::npos) << e.what();
  }
  const render::ViewSet mixed = render::uploadViews(context(), perspective);
  EXPECT_FALSE(mixed.raysInVoxelRows);
  EXPECT_THROW(render::rewriteViews(mixed, orbitCameras({0.0, 90.0}, grid, 6, 7)), Error);
}

INSTANTIATE_TEST_SUITE_P(LightOffOn, RendererTest, ::testing::Bool(),
                         [](const auto& param) { return param.param ? "Lit" : "Unlit"; });

TEST_F(GpuTest, ShadowPassMatchesReference) {
  const GridSize grid{.x = 9, .y = 5, .z = 7};
  const render::RenderSettings s = litSettings();
  std::vector<float> density;
  const Tensor volume = randomTensor(context(), grid.volume(), 31, 0.0f, 1.0f, &density);
  Tensor shadow = poisonedTensor(context(), volume.shape());
  Stream stream(context());
  render::lightTransmittance(stream, volume, s, shadow);
  stream.submit();
  EXPECT_TRUE(allClose(shadow, reference::lightTransmittance(toDouble(density), grid, *s.light), {1e-5, 1e-4}));
}

// A volume of `grid` with random values in [x0, x1) x [y0, y1) x [z0, z1) and zeros elsewhere, as smoke in a
// larger domain is.
struct Region {
  int64_t x0, x1, y0, y1, z0, z1;
};

std::vector<float> sparseSmoke(const GridSize& grid, uint64_t seed, const Region& r) {
  std::vector<float> values = randomValues(static_cast<std::size_t>(grid.x * grid.y * grid.z), seed, 0.0f, 1.5f);
  for (int64_t z = 0; z < grid.z; ++z)
    for (int64_t y = 0; y < grid.y; ++y)
      for (int64_t x = 0; x < grid.x; ++x)
        if (x < r.x0 || x >= r.x1 || y < r.y0 || y >= r.y1 || z < r.z0 || z >= r.z1)
          values[static_cast<std::size_t>((z * grid.y + y) * grid.x + x)] = 0.0f;
  return values;
}

// An occupied box that holds every sample a march can take: nothing is left out.
Tensor boxOfEverySample(Context& context) {
  return Tensor::fromHost(context, {2, 4}, std::vector<float>{-1e30f, -1e30f, -1e30f, 0, 1e30f, 1e30f, 1e30f, 0});
}

// Whether an occupied box (low, high as downloaded) is smaller than the box [-1/2, N + 1/2] of `grid` on some
// side, so that a march over it leaves samples out.
bool leavesSamplesOut(const std::vector<float>& b, const GridSize& grid) {
  return b[0] > -0.5f || b[1] > -0.5f || b[2] > -0.5f || b[4] < static_cast<float>(grid.x) + 0.5f ||
         b[5] < static_cast<float>(grid.y) + 0.5f || b[6] < static_cast<float>(grid.z) + 0.5f;
}

// The shadow pass and the march take only the samples in the density's occupied box; each one they leave out
// adds exactly 0, so both give the same bits as with a box that holds every sample (low -1e30, high 1e30), on
// sparse volumes of odd sizes, for lights along and across the axes and steps that are not whole voxels,
// through orbit and perspective cameras.
TEST_F(GpuTest, MarchesOverTheOccupiedBoxGiveTheSameBitsAsOverEverySample) {
  const Tensor everything = boxOfEverySample(context());
  const std::vector<Vec3> lights{{-0.5, 1.0, -1.0}, {0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.3, -0.9, 0.2}, {-1.0, -1.0, -1.0}};
  for (const GridSize grid : {GridSize{.x = 13, .y = 17, .z = 11}, GridSize{.x = 20, .y = 9, .z = 16}}) {
    const std::vector<Camera> cameras = mixedCameras(grid, static_cast<int>(grid.x), static_cast<int>(grid.y));
    const render::ViewSet views = render::uploadViews(context(), cameras);
    // Regions that start on block faces (where a stencil of the block before reads their first voxels) and
    // ones that do not.
    const std::vector<Region> regions{{4, 9, 8, 13, 4, 7}, {1, 6, 3, 9, 5, 11}, {7, 13, 0, 5, 2, 3}, {0, 20, 2, 4, 0, 16}};
    for (uint64_t seed = 71; seed < 71 + regions.size(); ++seed) {
      const Tensor volume = Tensor::fromHost(context(), grid.volume(), sparseSmoke(grid, seed, regions[seed - 71]));
      for (std::size_t l = 0; l <= lights.size(); ++l) {
        render::RenderSettings s = l == lights.size() ? unlitSettings() : litSettings();
        if (s.light) {
          s.light->direction = lights[l];
          s.light->step = l % 2 == 0 ? 0.7f : 1.3f;
        }
        s.step = l % 2 == 0 ? 0.9f : 0.55f;
        Stream stream(context());
        const Tensor box = render::occupiedBox(stream, volume);
        std::vector<Tensor> shadows, images;
        for (const Tensor* bounds : {&box, &everything}) {
          shadows.push_back(poisonedTensor(context(), grid.volume()));
          images.push_back(poisonedTensor(context(), {views.views, 1, views.height, views.width}));
          if (s.light) render::lightTransmittance(stream, volume, s, shadows.back(), bounds);
          render::march(stream, volume, s.light ? &shadows.back() : nullptr, views, s, images.back(), bounds);
        }
        stream.submit();
        const std::string where = "grid " + std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" +
                                  std::to_string(grid.z) + ", seed " + std::to_string(seed) + ", light " + std::to_string(l);
        EXPECT_TRUE(allClose(images[0], images[1].download(), {0.0, 0.0})) << "images, " << where;
        if (s.light) {
          EXPECT_TRUE(allClose(shadows[0], shadows[1].download(), {0.0, 0.0})) << "shadow, " << where;
        }
        EXPECT_TRUE(leavesSamplesOut(box.download(), grid)) << "the box holds the whole grid, so nothing was left out: " << where;
      }
    }
  }
}

// The light pass's adjoint takes only the samples in the occupied box of the shadow's gradient; the same bits as
// with a box that holds every sample, for gradients that are zero outside regions starting on block faces and
// between them, lights along and across the axes and steps that are not whole voxels.
TEST_F(GpuTest, LightAdjointOverTheOccupiedBoxGivesTheSameBitsAsOverEverySample) {
  const Tensor everything = boxOfEverySample(context());
  const std::vector<Vec3> lights{{-0.5, 1.0, -1.0}, {0.0, 1.0, 0.0}, {1.0, 0.0, 0.0}, {0.3, -0.9, 0.2}};
  const std::vector<Region> regions{{4, 9, 8, 13, 4, 7}, {1, 6, 3, 9, 5, 11}, {0, 20, 2, 4, 0, 16}};
  for (const GridSize grid : {GridSize{.x = 13, .y = 17, .z = 11}, GridSize{.x = 20, .y = 9, .z = 16}}) {
    const Tensor shadow = randomTensor(context(), grid.volume(), 81, 0.05f, 1.0f);
    const Tensor direct = randomTensor(context(), grid.volume(), 82);
    for (std::size_t r = 0; r < regions.size(); ++r) {
      const Tensor gradShadow = Tensor::fromHost(context(), grid.volume(), sparseSmoke(grid, 83 + r, regions[r]));
      for (std::size_t l = 0; l < lights.size(); ++l) {
        render::RenderSettings s = litSettings();
        s.light->direction = lights[l];
        s.light->step = l % 2 == 0 ? 0.7f : 1.3f;
        const Tensor box = poisonedTensor(context(), {2, 4});
        std::vector<Tensor> grads;
        Stream stream(context());
        for (const Tensor* bounds : {static_cast<const Tensor*>(nullptr), &everything}) {
          grads.push_back(poisonedTensor(context(), grid.volume()));
          render::lightTransmittanceBackward(stream, shadow, gradShadow, direct, s, grads.back(), bounds);
        }
        render::occupiedBox(stream, gradShadow, Tensor(context(), render::occupiedBlocksShape(grid)), box);
        stream.submit();
        const std::string where = "grid " + std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" +
                                  std::to_string(grid.z) + ", region " + std::to_string(r) + ", light " + std::to_string(l);
        EXPECT_TRUE(allClose(grads[0], grads[1].download(), {0.0, 0.0})) << where;
        EXPECT_TRUE(leavesSamplesOut(box.download(), grid)) << "the box holds the whole grid, so nothing was left out: " << where;
      }
    }
  }
}

TEST_F(GpuTest, FrontViewColumnsAreVoxelColumns) {
  // One lit voxel column along z at (x = 2, y = 3): the front view shows it at column 2, row H - 1 - 3.
  const GridSize grid{.x = 5, .y = 6, .z = 4};
  std::vector<float> density(static_cast<std::size_t>(4 * 6 * 5), 0.0f);
  for (int z = 0; z < 4; ++z) density[static_cast<std::size_t>((z * 6 + 3) * 5 + 2)] = 1.0f;
  const Tensor volume = Tensor::fromHost(context(), {4, 6, 5}, density);
  const std::vector<Camera> cameras = orbitCameras({0.0}, grid, 5, 6);
  const render::ViewSet views = render::uploadViews(context(), cameras);
  Tensor images = poisonedTensor(context(), {1, 1, 6, 5});
  Stream stream(context());
  render::render(stream, volume, views, unlitSettings(), images);
  stream.submit();
  const std::vector<float> image = images.download();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 5; ++c) {
      const float value = image[static_cast<std::size_t>(r * 5 + c)];
      if (r == 2 && c == 2) EXPECT_GT(value, 0.5f);
      else EXPECT_LT(value, 0.5f * image[2 * 5 + 2]) << "row " << r << " column " << c;
    }
}

TEST_F(GpuTest, RendererRejectsBadShapesAndSettings) {
  const GridSize grid{.x = 5, .y = 4, .z = 3};
  const Tensor volume(context(), {3, 4, 5});
  const render::ViewSet views = render::uploadViews(context(), orbitCameras({0.0, 90.0}, grid, 5, 4));
  Stream stream(context());
  EXPECT_THROW(render::render(stream, volume, views, unlitSettings(), Tensor(context(), {1, 1, 4, 5})), Error);
  EXPECT_THROW(render::render(stream, Tensor(context(), {2, 3, 4, 5}), views, unlitSettings(),
                              Tensor(context(), {2, 1, 4, 5})),
               Error);
  render::RenderSettings bad = unlitSettings();
  bad.step = 0;
  EXPECT_THROW(render::render(stream, volume, views, bad, Tensor(context(), {2, 1, 4, 5})), Error);
  const std::vector<Camera> mixed = {orbitCamera(0, grid, 5, 4), orbitCamera(0, grid, 4, 4)};
  EXPECT_THROW(render::uploadViews(context(), mixed), Error);
}

}  // namespace
}  // namespace smokesvd::testing
