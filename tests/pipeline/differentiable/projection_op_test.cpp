// The projection as an op: on the tape (forward equals the solver, backward is the projection of the
// upstream gradient, checked by the dot-product identity <P u, v> = <u, P v>) and through `smokesvd op`.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "pipeline/differentiable/projection.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/op_runner.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {


const GridSize kGrid{.x = 13, .y = 17, .z = 11};

// A closed box with an open top and a solid block inside.
std::vector<float> openTopFlags(const GridSize& grid) {
  std::vector<float> flags(static_cast<std::size_t>(grid.cells()));
  std::size_t index = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i, ++index) {
        const bool wall = i == 0 || k == 0 || j == 0 || i == grid.x - 1 || k == grid.z - 1;
        const bool block = i >= 4 && i < 7 && j >= 6 && j < 9 && k >= 3 && k < 6;
        flags[index] = wall || block ? 2.0f : (j == grid.y - 1 ? 4.0f : 1.0f);
      }
  return flags;
}

double dot(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += static_cast<double>(a[i]) * b[i];
  return sum;
}

std::shared_ptr<physics::PressureSolver> tightSolver(Context& context, const Tensor& flags) {
  physics::PressureOptions options;
  options.tolerance = 1e-6;
  options.absoluteTolerance = 1e-7;
  options.warmStart = false;
  return std::make_shared<physics::PressureSolver>(context, flags, options);
}

class ProjectOp : public GpuTest {};

TEST_F(ProjectOp, ForwardIsTheSolverAndBackwardProjectsTheGradient) {
  const Tensor flags = Tensor::fromHost(context(), kGrid.volume(), openTopFlags(kGrid));
  auto solver = tightSolver(context(), flags);
  const Tensor u = randomTensor(context(), kGrid.vector(), 5, -1, 1);
  const Tensor g = randomTensor(context(), kGrid.vector(), 6, -1, 1);

  Stream stream(context());
  Tape tape(stream);
  Var velocity = variable(u, true);
  Var projected = diff::project(tape, solver, velocity);
  tape.backward({{projected, g}});
  stream.submit();

  // Forward: exactly what the solver gives on its own.
  Tensor direct = poisonedTensor(context(), kGrid.vector());
  auto reference = tightSolver(context(), flags);
  ASSERT_TRUE(reference->project(u, direct).converged);
  const std::vector<float> pu = projected->value.download();
  EXPECT_EQ(pu, direct.download());

  // Backward: <P u, g> = <u, grad_u> with grad_u = P g; and grad_u is P g.
  const std::vector<float> gradU = velocity->grad.download();
  const double lhs = dot(pu, g.download()), rhs = dot(u.download(), gradU);
  EXPECT_NEAR(lhs, rhs, 1e-4 * (std::abs(lhs) + 1.0));
  Tensor pg = poisonedTensor(context(), kGrid.vector());
  ASSERT_TRUE(reference->project(g, pg).converged);
  EXPECT_TRUE(allClose(gradU, pg.download(), kGrid.vector(), {1e-6, 1e-6}));
}

TEST_F(ProjectOp, SymmetricInEveryDomain) {
  // Closed box (singular matrix, mean removed) and open top with an obstacle.
  std::vector<float> closed(static_cast<std::size_t>(kGrid.cells()), 1.0f);
  std::size_t index = 0;
  for (int64_t k = 0; k < kGrid.z; ++k)
    for (int64_t j = 0; j < kGrid.y; ++j)
      for (int64_t i = 0; i < kGrid.x; ++i, ++index)
        if (i == 0 || j == 0 || k == 0 || i == kGrid.x - 1 || j == kGrid.y - 1 || k == kGrid.z - 1) closed[index] = 2.0f;
  for (const std::vector<float>& flagValues : {closed, openTopFlags(kGrid)}) {
    const Tensor flags = Tensor::fromHost(context(), kGrid.volume(), flagValues);
    auto solver = tightSolver(context(), flags);
    const Tensor u = randomTensor(context(), kGrid.vector(), 7, -1, 1), v = randomTensor(context(), kGrid.vector(), 8, -1, 1);
    Tensor pu(context(), kGrid.vector()), pv(context(), kGrid.vector());
    ASSERT_TRUE(solver->project(u, pu).converged);
    ASSERT_TRUE(solver->project(v, pv).converged);
    const double a = dot(pu.download(), v.download()), b = dot(u.download(), pv.download());
    EXPECT_NEAR(a, b, 1e-4 * (std::abs(a) + 1.0));
  }
}

TEST(ProjectCommand, RunsForwardAndBackwardOnNpyFiles) {
  std::vector<float> velocity(static_cast<std::size_t>(3 * kGrid.cells()));
  for (std::size_t i = 0; i < velocity.size(); ++i) velocity[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i)));
  const std::vector<float> flagValues = openTopFlags(kGrid);
  const OpRun run = runOpCommand("project",
                                 {{"velocity", io::NpyArray::fromFloats(kGrid.vector(), velocity)},
                                  {"flags", io::NpyArray::fromFloats(kGrid.volume(), flagValues)},
                                  {"grad_out", io::NpyArray::fromFloats(kGrid.vector(), velocity)}},
                                 {"out", "grad_velocity"}, {"tolerance=1e-6"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const ref::FlagView view(kGrid, flagValues);
  const double before = ref::maxAbs(ref::divergence(view, ref::widen(velocity)));
  const double after = ref::maxAbs(ref::divergence(view, ref::widen(run.outputs.at("out").floats)));
  EXPECT_LE(after, 1e-6 * before + 1e-6);
  // The gradient of the same field is the same projection.
  EXPECT_EQ(run.outputs.at("grad_velocity").floats, run.outputs.at("out").floats);
}

TEST(ProjectCommand, UnconvergedSolveIsAnError) {
  const std::vector<float> velocity(static_cast<std::size_t>(3 * kGrid.cells()), 0.5f);
  std::vector<float> noisy = velocity;
  for (std::size_t i = 0; i < noisy.size(); ++i) noisy[i] += static_cast<float>(std::cos(1.3 * static_cast<double>(i)));
  const OpRun run = runOpCommand("project", {{"velocity", io::NpyArray::fromFloats(kGrid.vector(), noisy)}}, {"out"},
                                 {"tolerance=1e-7", "max_iterations=1"});
  EXPECT_NE(run.exitCode, 0);
  EXPECT_NE(run.err.find("did not converge"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace smokesvd::testing
