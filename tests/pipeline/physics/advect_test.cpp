// Advection kernels against the CPU reference (forward) and finite differences of the reference in
// double (adjoints), on small odd-sized grids with random flags (interior obstacles and empty cells),
// random fields and velocities fast enough to cross several cells and hit the lookup clamps.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/advect_reference.h"

namespace smokesvd::testing {
namespace {

using physics::AdvectionScheme;

struct Variant {
  AdvectionScheme scheme;
  bool mac;
};

std::string describe(const Variant& variant) {
  return std::string(variant.scheme == AdvectionScheme::SemiLagrangian ? "SemiLagrangian" : "MacCormack") +
         (variant.mac ? "Mac" : "Scalar");
}
void PrintTo(const Variant& variant, std::ostream* out) { *out << describe(variant); }
std::string variantName(const ::testing::TestParamInfo<Variant>& info) { return describe(info.param); }

AdvectionCase<float> randomCase(ReferenceGrid grid, bool mac, bool withInflow, uint64_t seed, float speed) {
  AdvectionCase<float> input;
  input.grid = grid;
  input.mac = mac;
  const int cells = grid.cells();
  const std::vector<float> kinds = randomValues(cells, seed, 0.0f, 1.0f);
  input.flags = physics::closedBoxFlags({.x = grid.x, .y = grid.y, .z = grid.z});
  for (int i = 0; i < cells; ++i) {
    if (input.flags[i] != static_cast<float>(physics::kFluid)) continue;
    if (kinds[i] < 0.08f)
      input.flags[i] = static_cast<float>(physics::kObstacle);
    else if (kinds[i] < 0.16f)
      input.flags[i] = static_cast<float>(physics::kEmpty);
  }
  const int planes = mac ? 3 : 1;
  input.field = randomValues(planes * cells, seed + 1, -1.0f, 1.0f);
  input.velocity = randomValues(3 * cells, seed + 2, -speed, speed);
  if (withInflow) input.inflow = randomValues(planes * cells, seed + 3, 0.0f, 0.5f);
  return input;
}

AdvectionCase<double> widened(const AdvectionCase<float>& input) {
  AdvectionCase<double> result;
  result.grid = input.grid;
  result.flags = input.flags;
  result.mac = input.mac;
  result.field = toDouble(input.field);
  result.velocity = toDouble(input.velocity);
  result.inflow = toDouble(input.inflow);
  return result;
}

// Adds a flow turning about the vertical line x = X/2, z = Z/2, `rate` cells per frame per cell of
// distance, and rising at 1.5 - 0.1 y.
AdvectionCase<float> swirled(AdvectionCase<float> input, double rate) {
  const ReferenceGrid& grid = input.grid;
  const double cx = grid.x / 2.0, cz = grid.z / 2.0;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < grid.z; ++k)
      for (int j = 0; j < grid.y; ++j)
        for (int i = 0; i < grid.x; ++i) {
          const double swirl = c == 0 ? -rate * (k - cz) : c == 2 ? rate * (i - cx) : 1.5 - 0.1 * j;
          input.velocity[c * grid.cells() + grid.index(i, j, k)] += static_cast<float>(swirl);
        }
  return input;
}

// The case on the GPU, with the flag grid's masks recorded into `stream`.
struct GpuCase {
  GpuCase(Stream& stream, const AdvectionCase<float>& input)
      : flags(stream, Tensor::fromHost(stream.context(), {input.grid.z, input.grid.y, input.grid.x}, input.flags)),
        field(
            Tensor::fromHost(stream.context(), input.mac ? flags.size().vector() : flags.size().volume(), input.field)),
        velocity(Tensor::fromHost(stream.context(), flags.size().vector(), input.velocity)) {
    if (!input.inflow.empty()) inflow = Tensor::fromHost(stream.context(), field.shape(), input.inflow);
  }
  physics::FlagGrid flags;
  Tensor field, velocity, inflow;
};

class AdvectTest : public GpuTest, public ::testing::WithParamInterface<Variant> {
 protected:
  physics::AdvectionParams params(float dt = 1.0f) const { return {.scheme = GetParam().scheme, .dt = dt}; }

  void checkForward(const ReferenceGrid& grid, bool withInflow, uint64_t seed, float speed, float dt) {
    const AdvectionCase<float> input = randomCase(grid, GetParam().mac, withInflow, seed, speed);
    Stream stream(context());
    const GpuCase gpu(stream, input);
    // Without a cache (the simulator's path) and with one (training's path, MacCormack keeps its
    // first pass for the adjoint): two kernel sequences, the same values.
    Tensor out = poisonedTensor(context(), gpu.field.shape());
    Tensor outCached = poisonedTensor(context(), gpu.field.shape());
    physics::AdvectionCache cache;
    const Tensor* inflow = withInflow ? &gpu.inflow : nullptr;
    physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, inflow, params(dt), out);
    physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, inflow, params(dt), outCached, &cache);
    stream.submit();
    AdvectionDiagnostics diagnostics;
    const std::vector<float> expected = referenceAdvect(input, params(dt), &diagnostics);
    EXPECT_TRUE(allClose(out, expected, {1e-5, 1e-5}));
    EXPECT_EQ(out.download(), outCached.download());
    if (GetParam().scheme == AdvectionScheme::MacCormack) {
      EXPECT_GT(diagnostics.kept, 0);
      EXPECT_GT(diagnostics.reverted, 0);
    }
  }
};

TEST_P(AdvectTest, ForwardMatchesReference) { checkForward({7, 9, 5}, false, 11, 1.6f, 1.0f); }

TEST_P(AdvectTest, ForwardWithInflowAndFastFlowMatchesReference) { checkForward({9, 5, 7}, true, 21, 4.0f, 0.8f); }

// Gradients w.r.t. the advected field and the velocity, each with the other input held fixed, every
// element against central differences of the reference.
void checkBackward(const AdvectionCase<float>& input, const physics::AdvectionParams& p, uint64_t seed) {
  Context& context = testContext();
  const AdvectionCase<double> exact = widened(input);
  AdvectionDiagnostics diagnostics;
  referenceAdvect(exact, p, &diagnostics);
  ASSERT_GT(diagnostics.margin, 1e-5) << "a finite-difference step would cross a switch point; pick another seed";
  if (p.scheme == AdvectionScheme::MacCormack) {
    EXPECT_GT(diagnostics.kept, 0);
    EXPECT_GT(diagnostics.reverted, 0);
  }

  Stream stream(context);
  const GpuCase gpu(stream, input);
  std::vector<float> upstream;
  Tensor gradOut = randomTensor(context, gpu.field.shape(), seed, -1.0f, 1.0f, &upstream);
  physics::AdvectionCache cache;
  Tensor out(context, gpu.field.shape());
  Tensor gradField = poisonedTensor(context, gpu.field.shape());
  Tensor gradVelocity = poisonedTensor(context, gpu.velocity.shape());
  physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, nullptr, p, out, &cache);
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, p, gradOut, &cache,
                          {.field = &gradField, .velocity = &gradVelocity});
  stream.submit();

  const std::vector<double> g = toDouble(upstream);
  const std::vector<double> expectedField = numericVjp(
      [&](std::span<const double> field) {
        AdvectionCase<double> moved = exact;
        moved.field.assign(field.begin(), field.end());
        return referenceAdvect(moved, p);
      },
      exact.field, g);
  const std::vector<double> expectedVelocity = numericVjp(
      [&](std::span<const double> velocity) {
        AdvectionCase<double> moved = exact;
        moved.velocity.assign(velocity.begin(), velocity.end());
        return referenceAdvect(moved, p);
      },
      exact.velocity, g);
  EXPECT_TRUE(allClose(gradField, expectedField, {2e-5, 1e-4}));
  EXPECT_TRUE(allClose(gradVelocity, expectedVelocity, {2e-5, 1e-4}));
}

TEST_P(AdvectTest, BackwardMatchesFiniteDifferences) {
  checkBackward(randomCase({7, 9, 5}, GetParam().mac, false, 41, 1.6f), params(0.9f), 42);
}

// The same on a grid of two gather tiles along every axis (8^3 cells each), with a swirl so that the
// tiles' windows differ.
TEST_P(AdvectTest, BackwardMatchesFiniteDifferencesAcrossTilesElementByElement) {
  const ReferenceGrid grid{10, 9, 11};
  checkBackward(swirled(randomCase(grid, GetParam().mac, false, 71, 0.6f), 0.2), params(1.0f), 72);
}

// Without the forward's cache the backward recomputes it and gives the same gradients.
TEST_P(AdvectTest, BackwardWithoutCacheRecomputesIt) {
  const AdvectionCase<float> input = randomCase({5, 7, 5}, GetParam().mac, false, 51, 1.2f);
  Stream stream(context());
  const GpuCase gpu(stream, input);
  Tensor gradOut = randomTensor(context(), gpu.field.shape(), 52);
  physics::AdvectionCache cache;
  Tensor out(context(), gpu.field.shape());
  Tensor saved(context(), gpu.velocity.shape());
  Tensor recomputed = poisonedTensor(context(), gpu.velocity.shape());
  physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, nullptr, params(), out, &cache);
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, params(), gradOut, &cache, {.velocity = &saved});
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, params(), gradOut, nullptr,
                          {.velocity = &recomputed});
  stream.submit();
  EXPECT_TRUE(allClose(recomputed, saved.download(), {0, 0}));
}

// On a grid of many gather tiles with a spatially varying flow (so the tiles' windows differ), the
// gradients' projections on random directions match central differences of the reference along them.
TEST_P(AdvectTest, BackwardMatchesDirectionalDerivativesAcrossTiles) {
  const AdvectionCase<float> input = swirled(randomCase({21, 13, 18}, GetParam().mac, false, 61, 0.3f), 0.22);
  const AdvectionCase<double> exact = widened(input);
  const physics::AdvectionParams p = params(1.0f);
  AdvectionDiagnostics diagnostics;
  referenceAdvect(exact, p, &diagnostics);
  ASSERT_GT(diagnostics.margin, 1e-6) << "a finite-difference step would cross a switch point; pick another seed";

  Stream stream(context());
  const GpuCase gpu(stream, input);
  std::vector<float> upstream;
  Tensor gradOut = randomTensor(context(), gpu.field.shape(), 62, -1.0f, 1.0f, &upstream);
  Tensor out(context(), gpu.field.shape());
  Tensor gradField = poisonedTensor(context(), gpu.field.shape());
  Tensor gradVelocity = poisonedTensor(context(), gpu.velocity.shape());
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, p, gradOut, nullptr,
                          {.field = &gradField, .velocity = &gradVelocity});
  stream.submit();

  auto directional = [&](bool alongVelocity, const std::vector<float>& direction) {
    const double h = 1e-7;
    auto moved = [&](double sign) {
      AdvectionCase<double> point = exact;
      std::vector<double>& values = alongVelocity ? point.velocity : point.field;
      for (std::size_t i = 0; i < values.size(); ++i) values[i] += sign * h * direction[i];
      const std::vector<double> result = referenceAdvect(point, p);
      double projected = 0;
      for (std::size_t i = 0; i < result.size(); ++i) projected += upstream[i] * result[i];
      return projected;
    };
    return (moved(1) - moved(-1)) / (2 * h);
  };
  auto dot = [](const std::vector<float>& a, const std::vector<float>& b) {
    double total = 0;
    for (std::size_t i = 0; i < a.size(); ++i) total += static_cast<double>(a[i]) * b[i];
    return total;
  };
  const std::vector<float> fieldDirection = randomValues(exact.field.size(), 63);
  const std::vector<float> velocityDirection = randomValues(exact.velocity.size(), 64);
  const double expectedField = directional(false, fieldDirection);
  const double expectedVelocity = directional(true, velocityDirection);
  EXPECT_NEAR(dot(gradField.download(), fieldDirection), expectedField, 1e-4 * std::abs(expectedField) + 1e-3);
  EXPECT_NEAR(dot(gradVelocity.download(), velocityDirection), expectedVelocity,
              1e-4 * std::abs(expectedVelocity) + 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Schemes, AdvectTest,
                         ::testing::Values(Variant{AdvectionScheme::SemiLagrangian, false},
                                           Variant{AdvectionScheme::MacCormack, false},
                                           Variant{AdvectionScheme::SemiLagrangian, true},
                                           Variant{AdvectionScheme::MacCormack, true}),
                         variantName);

TEST_F(GpuTest, MacSelfAdvectionMatchesReference) {
  for (AdvectionScheme scheme : {AdvectionScheme::SemiLagrangian, AdvectionScheme::MacCormack}) {
    AdvectionCase<float> input = randomCase({7, 6, 9}, true, false, 31, 1.3f);
    input.field = input.velocity;
    Stream stream(context());
    const GpuCase gpu(stream, input);
    Tensor out = poisonedTensor(context(), gpu.velocity.shape());
    const physics::AdvectionParams params{.scheme = scheme};
    physics::advect(stream, gpu.flags, gpu.velocity, gpu.velocity, nullptr, params, out);
    stream.submit();
    EXPECT_TRUE(allClose(out, referenceAdvect(input, params), {1e-5, 1e-5})) << describe({scheme, true});
  }
}

TEST_F(GpuTest, AdvectRejectsMismatchedShapes) {
  const GridSize grid{.x = 5, .y = 6, .z = 7};
  Stream stream(context());
  const physics::FlagGrid flags(stream, physics::closedBoxFlagsTensor(context(), grid));
  Tensor field(context(), grid.volume());
  Tensor velocity(context(), {3, 7, 6, 4});
  Tensor out(context(), grid.volume());
  EXPECT_THROW(physics::advect(stream, flags, field, velocity, nullptr, {}, out), Error);
  EXPECT_THROW(physics::FlagGrid(stream, physics::closedBoxFlagsTensor(context(), {.x = 2, .y = 6, .z = 7})), Error);
}

}  // namespace
}  // namespace smokesvd::testing
