#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pipeline/physics/pressure.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {


enum class Domain { ClosedBox, ClosedWithObstacles, OpenTop, OpenTopWithObstacles };

std::vector<float> domainFlags(const GridSize& grid, Domain domain) {
  std::vector<float> flags(static_cast<std::size_t>(grid.cells()));
  const bool openTop = domain == Domain::OpenTop || domain == Domain::OpenTopWithObstacles;
  const bool obstacles = domain == Domain::ClosedWithObstacles || domain == Domain::OpenTopWithObstacles;
  std::size_t index = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i, ++index) {
        const bool side = i == 0 || k == 0 || i == grid.x - 1 || k == grid.z - 1 || j == 0;
        const bool top = j == grid.y - 1;
        // A sphere and a box in the middle of the domain.
        auto offset = [](int64_t cell, int64_t size, double at) {
          return static_cast<double>(cell) + 0.5 - static_cast<double>(size) * at;
        };
        const double dx = offset(i, grid.x, 0.4), dy = offset(j, grid.y, 0.55), dz = offset(k, grid.z, 0.5);
        const bool sphere = dx * dx + dy * dy + dz * dz < 9.0;
        const bool box = std::abs(offset(i, grid.x, 0.7)) < 2 && std::abs(offset(j, grid.y, 0.3)) < 3 &&
                         std::abs(offset(k, grid.z, 0.4)) < 2.5;
        const bool solid = side || (top && !openTop) || (obstacles && (sphere || box));
        flags[index] = solid ? 2.0f : (top ? 4.0f : 1.0f);
      }
  return flags;
}

class ProjectionTest : public GpuTest, public ::testing::WithParamInterface<Domain> {};

TEST_P(ProjectionTest, LeavesDivergenceUnderTheTolerance) {
  const GridSize grid{.x = 19, .y = 27, .z = 17};
  const std::vector<float> flagValues = domainFlags(grid, GetParam());
  const ref::FlagView view(grid, flagValues);
  Tensor flags = Tensor::fromHost(context(), grid.volume(), flagValues);
  std::vector<float> velocityValues;
  Tensor velocity = randomTensor(context(), grid.vector(), 17, -1, 1, &velocityValues);
  Tensor projected = poisonedTensor(context(), grid.vector());

  for (double tolerance : {1e-3, 1e-5}) {
    physics::PressureOptions options;
    options.tolerance = tolerance;
    options.warmStart = false;
    physics::PressureSolver solver(context(), flags, options);
    const physics::PressureReport report = solver.project(velocity, projected);

    // max |div u| over fluid cells, before and after, computed on the CPU in double.
    const double before = ref::maxAbs(ref::divergence(view, ref::widen(velocityValues)));
    const std::vector<float> after = projected.download();
    const double remaining = ref::maxAbs(ref::divergence(view, ref::widen(after)));
    EXPECT_TRUE(report.converged) << "tolerance " << tolerance;
    EXPECT_LT(report.iterations, 40) << "tolerance " << tolerance;
    EXPECT_NEAR(report.initialDivergence, before, 1e-5 * before);
    EXPECT_LE(report.relativeResidual, tolerance);
    // The divergence left is the solver's final residual, up to float rounding in the correction.
    EXPECT_LE(remaining, tolerance * before + 2e-6) << "tolerance " << tolerance;
    // Faces touching an obstacle carry no flow; every number is finite.
    const int64_t cells = grid.cells();
    for (int64_t index = 0; index < cells; ++index) {
      const ref::Cell c = view.cell(index);
      for (int a = 0; a < 3; ++a) {
        const float u = after[a * cells + index];
        ASSERT_TRUE(std::isfinite(u));
        if (view.obstacle(c) || view.obstacle(ref::step(c, a, -1))) {
          ASSERT_EQ(u, 0.0f);
        }
      }
    }
  }
}

TEST_P(ProjectionTest, ProjectingTwiceChangesNothing) {
  const GridSize grid{.x = 13, .y = 15, .z = 11};
  Tensor flags = Tensor::fromHost(context(), grid.volume(), domainFlags(grid, GetParam()));
  Tensor velocity = randomTensor(context(), grid.vector(), 5, -1, 1);
  Tensor once(context(), grid.vector()), twice(context(), grid.vector());
  physics::PressureOptions options;
  options.tolerance = 1e-5;
  physics::PressureSolver solver(context(), flags, options);
  solver.project(velocity, once);
  solver.project(once, twice);
  const std::vector<float> a = once.download(), b = twice.download();
  double change = 0, magnitude = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    change = std::max(change, static_cast<double>(std::abs(a[i] - b[i])));
    magnitude = std::max(magnitude, static_cast<double>(std::abs(a[i])));
  }
  EXPECT_LE(change, 1e-4 * magnitude);
}

// Not only properties a projection onto zero also has: the result is u − ∇p for the pressure the solver
// returns (with p = 0 in empty cells and no flow through obstacle faces), that p is not zero, and most of
// a random field survives (a random field is far from a gradient).
TEST_P(ProjectionTest, TheCorrectionIsTheGradientOfTheReturnedPressure) {
  const GridSize grid{.x = 12, .y = 14, .z = 10};
  const std::vector<float> flagValues = domainFlags(grid, GetParam());
  const ref::FlagView view(grid, flagValues);
  Tensor flags = Tensor::fromHost(context(), grid.volume(), flagValues);
  std::vector<float> velocityValues;
  Tensor velocity = randomTensor(context(), grid.vector(), 23, -1, 1, &velocityValues);
  Tensor projected = poisonedTensor(context(), grid.vector());
  physics::PressureOptions options;
  options.tolerance = 1e-6;
  options.warmStart = false;
  physics::PressureSolver solver(context(), flags, options);
  ASSERT_TRUE(solver.project(velocity, projected).converged);
  const std::vector<float> pressure = solver.pressure();
  const ref::Field expected = ref::correctVelocity(view, ref::widen(pressure), ref::widen(velocityValues));
  const std::vector<float> after = projected.download();
  double pressureNorm = 0, projectedNorm = 0, inputNorm = 0;
  for (float p : pressure) pressureNorm += static_cast<double>(p) * p;
  for (std::size_t i = 0; i < after.size(); ++i) {
    ASSERT_NEAR(after[i], expected[i], 1e-4) << "velocity element " << i;
    projectedNorm += static_cast<double>(after[i]) * after[i];
    inputNorm += static_cast<double>(velocityValues[i]) * velocityValues[i];
  }
  EXPECT_GT(pressureNorm, 1.0);
  EXPECT_GT(projectedNorm, 0.1 * inputNorm);
  EXPECT_LT(projectedNorm, inputNorm);  // a projection never adds energy
}

// A velocity holding NaN or infinity is never reported as converged: a GPU max() may drop a NaN, the
// solver's sums do not.
TEST_P(ProjectionTest, NonFiniteVelocityIsNeverConverged) {
  const GridSize grid{.x = 9, .y = 11, .z = 8};
  Tensor flags = Tensor::fromHost(context(), grid.volume(), domainFlags(grid, GetParam()));
  for (float bad : {std::nanf(""), std::numeric_limits<float>::infinity()}) {
    std::vector<float> values = randomValues(static_cast<std::size_t>(3 * grid.cells()), 29, -1, 1);
    // u_x between fluid cells (1, 2, 2) and (2, 2, 2) in every domain
    values[static_cast<std::size_t>(2 * grid.x * grid.y + 2 * grid.x + 2)] = bad;
    Tensor velocity = Tensor::fromHost(context(), grid.vector(), values);
    Tensor projected = poisonedTensor(context(), grid.vector());
    physics::PressureSolver solver(context(), flags);
    const physics::PressureReport report = solver.project(velocity, projected);
    EXPECT_FALSE(report.finite) << bad;
    EXPECT_FALSE(report.converged) << bad;
  }
}

std::string domainName(const ::testing::TestParamInfo<Domain>& param) {
  const char* const names[] = {"ClosedBox", "ClosedWithObstacles", "OpenTop", "OpenTopWithObstacles"};
  return names[static_cast<int>(param.param)];
}

INSTANTIATE_TEST_SUITE_P(Domains, ProjectionTest,
                         ::testing::Values(Domain::ClosedBox, Domain::ClosedWithObstacles, Domain::OpenTop,
                                           Domain::OpenTopWithObstacles),
                         domainName);

}  // namespace
}  // namespace smokesvd::testing
