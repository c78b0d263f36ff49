#include <gtest/gtest.h>

#include "nets/io/npy.h"
#include "pipeline/differentiable/render.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/pipeline/render/reference.h"
#include "tests/pipeline/render/scenes.h"

namespace smokesvd::testing {
namespace {

TEST_F(GpuTest, TapeRenderOfRotatedVolumeMatchesFiniteDifferences) {
  // loss = <g, render(rotate(density, 30))>: gradients flow through both ops on the tape.
  const GridSize grid{.x = 5, .y = 6, .z = 5};
  const std::vector<Camera> cameras = orbitCameras({0.0, 90.0}, grid, 5, 6);
  const render::RenderSettings s = litSettings();
  std::vector<float> density, upstream;
  Stream stream(context());
  Tape tape(stream);
  Var x = variable(randomTensor(context(), {5, 6, 5}, 71, 0, 1, &density), true);
  const render::ViewSet views = render::uploadViews(context(), cameras);
  Var images = diff::render(tape, diff::rotate(tape, x, 30.0), views, s);
  const Tensor seed = randomTensor(context(), images->value.shape(), 72, -1, 1, &upstream);
  tape.backward({{images, seed}});
  stream.submit();
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> v) {
        return reference::render(reference::rotate({v.begin(), v.end()}, 1, grid, 30.0), grid, cameras, s);
      },
      toDouble(density), toDouble(upstream));
  EXPECT_TRUE(allClose(x->grad, expected, {2e-4, 2e-3}));
}

TEST_F(GpuTest, TapeLiftGivesImageGradients) {
  const GridSize grid{.x = 5, .y = 4, .z = 3};
  const std::vector<Camera> cameras = orbitCameras({0.0, 45.0}, grid, 5, 4);
  std::vector<float> images, upstream;
  Stream stream(context());
  Tape tape(stream);
  Var x = variable(randomTensor(context(), {2, 1, 4, 5}, 73, 0, 1, &images), true);
  Var lifted = diff::lift(tape, x, render::uploadViews(context(), cameras), grid);
  ASSERT_EQ(lifted->value.shape(), (Shape{1, 2, 3, 4, 5}));
  const Tensor seed = randomTensor(context(), lifted->value.shape(), 74, -1, 1, &upstream);
  tape.backward({{lifted, seed}});
  stream.submit();
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> v) { return reference::lift({v.begin(), v.end()}, cameras, grid); },
      toDouble(images), toDouble(upstream));
  EXPECT_TRUE(allClose(x->grad, expected, {1e-4, 1e-4}));
}

TEST_F(GpuTest, OpRunnerRendersForwardAndBackward) {
  const GridSize grid{.x = 6, .y = 7, .z = 5};
  const std::vector<float> density = randomValues(5 * 7 * 6, 81, 0, 1);
  const std::vector<float> upstream = randomValues(2 * 7 * 6, 82, -1, 1);
  const OpRun run = runOpCommand(
      "render",
      {{"density", io::NpyArray::fromFloats({5, 7, 6}, density)}, {"grad_images", io::NpyArray::fromFloats({2, 1, 7, 6}, upstream)}},
      {"images", "grad_density"}, {"angles=0,90", "absorption=0.7", "light=0,1,-1", "ambient=0.2"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  render::RenderSettings s;
  s.absorption = 0.7f;
  s.ambient = 0.2f;
  s.light = render::DirectionalLight{{0, 1, -1}, 1.0f, 1.0f, 1.0f};
  const std::vector<Camera> cameras = orbitCameras({0.0, 90.0}, grid, 6, 7);
  const io::NpyArray& images = run.outputs.at("images");
  EXPECT_TRUE(allClose(images.floats, reference::render(toDouble(density), grid, cameras, s), images.shape,
                       {2e-5, 2e-4}));
  const io::NpyArray& gradient = run.outputs.at("grad_density");
  const std::vector<double> expected = numericVjp(
      [&](std::span<const double> v) { return reference::render({v.begin(), v.end()}, grid, cameras, s); },
      toDouble(density), toDouble(upstream));
  EXPECT_TRUE(allClose(gradient.floats, expected, gradient.shape, {2e-4, 2e-3}));
}

}  // namespace
}  // namespace smokesvd::testing
