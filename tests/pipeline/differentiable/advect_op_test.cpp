// The autograd wrappers of the physics ops and their `smokesvd op` registrations.
#include <gtest/gtest.h>

#include "nets/io/npy.h"
#include "pipeline/differentiable/physics.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"
#include "tests/harness/test_data.h"

namespace smokesvd::testing {
namespace {

const GridSize kGrid{.x = 7, .y = 6, .z = 5};

// Self-advection through the tape: the velocity's gradient is the sum of its two roles, and the
// inflow's is the upstream gradient.
TEST_F(GpuTest, AdvectOnTheTapeSumsBothRolesOfTheVelocity) {
  Stream stream(context());
  const physics::FlagGrid grid(stream, physics::closedBoxFlagsTensor(context(), kGrid));
  Tensor velocityValues = randomTensor(context(), kGrid.vector(), 1, -0.8f, 0.8f);
  Tensor inflowValues = randomTensor(context(), kGrid.vector(), 2);
  Tensor upstream = randomTensor(context(), kGrid.vector(), 3);
  const physics::AdvectionParams params{.scheme = physics::AdvectionScheme::MacCormack};

  Tape tape(stream);
  Var velocity = variable(velocityValues, true);
  Var inflow = variable(inflowValues, true);
  Var out = diff::advect(tape, grid, velocity, velocity, inflow, params);
  tape.backward({{out, upstream}});

  Tensor asField(context(), kGrid.vector()), asVelocity(context(), kGrid.vector());
  physics::advectBackward(stream, grid, velocityValues, velocityValues, params, upstream, nullptr,
                          {.field = &asField, .velocity = &asVelocity});
  stream.submit();
  const std::vector<float> field = asField.download(), role = asVelocity.download();
  std::vector<float> expected(field.size());
  for (std::size_t i = 0; i < field.size(); ++i) expected[i] = field[i] + role[i];
  EXPECT_TRUE(allClose(velocity->grad, expected, {1e-6, 1e-6}));
  EXPECT_TRUE(allClose(inflow->grad, upstream.download(), {0, 0}));
}

TEST_F(GpuTest, PaperVelocityLossOnTheTape) {
  Stream stream(context());
  Tape tape(stream);
  Var velocity = variable(randomTensor(context(), kGrid.vector(), 4), true);
  Var divergence = diff::divergence(tape, velocity, physics::Staggering::Centred);
  Var gradientNorm = diff::gradientNormSquared(tape, velocity);
  Tensor ones = Tensor::fromHost(context(), kGrid.volume(), std::vector<float>(kGrid.cells(), 1.0f));
  tape.backward({{divergence, divergence->value}, {gradientNorm, ones}});  // ½‖div‖² + ‖∇u‖²
  Tensor expectedDivergence(context(), kGrid.vector()), expectedNorm(context(), kGrid.vector());
  physics::divergenceBackward(stream, physics::Staggering::Centred, divergence->value, expectedDivergence);
  physics::gradientNormSquaredBackward(stream, velocity->value, ones, expectedNorm);
  stream.submit();
  const std::vector<float> a = expectedDivergence.download(), b = expectedNorm.download();
  std::vector<float> expected(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) expected[i] = a[i] + b[i];
  EXPECT_TRUE(allClose(velocity->grad, expected, {1e-5, 1e-5}));
}

// mantaflow's advection test case through the op runner: MAC velocity from the file layout, then
// MacCormack forward, and a backward whose gradients have the inputs' shapes.
TEST_F(GpuTest, AdvectsMantaflowCaseThroughTheOpCommand) {
  const auto arrays = io::readNpz(testData("mantaflow/advect_32x48x32.npz"));
  const OpRun planar = runOpCommand("velocity_to_planar", {{"x", arrays.at("vel_mac")}}, {"y"});
  ASSERT_EQ(planar.exitCode, 0) << planar.err;
  const io::NpyArray& velocity = planar.outputs.at("y");
  const io::NpyArray& density = arrays.at("density_in");

  const OpRun forward = runOpCommand(
      "advect", {{"field", density}, {"velocity", velocity}, {"flags", arrays.at("flags")}}, {"out"}, {"order=2"});
  ASSERT_EQ(forward.exitCode, 0) << forward.err;
  EXPECT_TRUE(allClose(forward.outputs.at("out").floats, arrays.at("density_mc").floats, arrays.at("density_mc").shape,
                       {1e-6, 1e-6}));

  const io::NpyArray ones = io::NpyArray::fromFloats(density.shape, std::vector<float>(density.numel(), 1.0f));
  const OpRun backward = runOpCommand("advect", {{"field", density}, {"velocity", velocity}, {"grad_out", ones}},
                                      {"grad_field", "grad_velocity"}, {"order=1"});
  ASSERT_EQ(backward.exitCode, 0) << backward.err;
  EXPECT_EQ(backward.outputs.at("grad_field").shape, density.shape);
  EXPECT_EQ(backward.outputs.at("grad_velocity").shape, (Shape{3, 32, 48, 32}));

  const OpRun bad = runOpCommand("advect", {{"field", density}, {"velocity", velocity}}, {"out"}, {"order=3"});
  EXPECT_NE(bad.exitCode, 0);
  EXPECT_NE(bad.err.find("order=3"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace smokesvd::testing
