// Advection kernels against the CPU reference (forward) and finite differences of the reference in
// double (adjoints), on small odd-sized grids with random flags (interior obstacles and empty cells),
// random fields and velocities fast enough to cross several cells and hit the lookup clamps.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/gradcheck.h"
#include "tests/harness/random.h"
#include "tests/physics/advect_reference.h"

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
  input.flags = physics::closedBoxFlags({grid.x, grid.y, grid.z});
  for (int i = 0; i < cells; ++i) {
    if (input.flags[i] != static_cast<float>(physics::kFluid)) continue;
    if (kinds[i] < 0.08f) input.flags[i] = static_cast<float>(physics::kObstacle);
    else if (kinds[i] < 0.16f) input.flags[i] = static_cast<float>(physics::kEmpty);
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

struct GpuCase {
  Tensor flags, field, velocity, inflow;
};

GpuCase upload(Context& context, const AdvectionCase<float>& input) {
  const ReferenceGrid& g = input.grid;
  const Shape volume{g.z, g.y, g.x};
  const Shape vector{3, g.z, g.y, g.x};
  GpuCase gpu{Tensor::fromHost(context, volume, input.flags),
              Tensor::fromHost(context, input.mac ? vector : volume, input.field),
              Tensor::fromHost(context, vector, input.velocity), Tensor()};
  if (!input.inflow.empty()) gpu.inflow = Tensor::fromHost(context, gpu.field.shape(), input.inflow);
  return gpu;
}

class AdvectTest : public GpuTest, public ::testing::WithParamInterface<Variant> {
 protected:
  physics::AdvectionParams params(float dt = 1.0f) const { return {.scheme = GetParam().scheme, .dt = dt}; }

  void checkForward(const ReferenceGrid& grid, bool withInflow, uint64_t seed, float speed, float dt) {
    const AdvectionCase<float> input = randomCase(grid, GetParam().mac, withInflow, seed, speed);
    const GpuCase gpu = upload(context(), input);
    Tensor out = poisonedTensor(context(), gpu.field.shape());
    Stream stream(context());
    physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, withInflow ? &gpu.inflow : nullptr, params(dt), out);
    stream.submit();
    AdvectionDiagnostics diagnostics;
    const std::vector<float> expected = referenceAdvect(input, params(dt), &diagnostics);
    EXPECT_TRUE(allClose(out, expected, {1e-5, 1e-5}));
    if (GetParam().scheme == AdvectionScheme::MacCormack) {
      EXPECT_GT(diagnostics.kept, 0);
      EXPECT_GT(diagnostics.reverted, 0);
    }
  }
};

TEST_P(AdvectTest, ForwardMatchesReference) { checkForward({7, 9, 5}, false, 11, 1.6f, 1.0f); }

TEST_P(AdvectTest, ForwardWithInflowAndFastFlowMatchesReference) { checkForward({9, 5, 7}, true, 21, 4.0f, 0.8f); }

TEST_P(AdvectTest, MacSelfAdvectionMatchesReference) {
  if (!GetParam().mac) GTEST_SKIP() << "self-advection is a MAC-field case";
  AdvectionCase<float> input = randomCase({7, 6, 9}, true, false, 31, 1.3f);
  input.field = input.velocity;
  const GpuCase gpu = upload(context(), input);
  Tensor out = poisonedTensor(context(), gpu.velocity.shape());
  Stream stream(context());
  physics::advect(stream, gpu.flags, gpu.velocity, gpu.velocity, nullptr, params(), out);
  stream.submit();
  EXPECT_TRUE(allClose(out, referenceAdvect(input, params()), {1e-5, 1e-5}));
}

// Gradients w.r.t. the advected field and the velocity, each with the other input held fixed.
TEST_P(AdvectTest, BackwardMatchesFiniteDifferences) {
  const AdvectionCase<float> input = randomCase({7, 9, 5}, GetParam().mac, false, 41, 1.6f);
  const AdvectionCase<double> exact = widened(input);
  const physics::AdvectionParams p = params(0.9f);
  AdvectionDiagnostics diagnostics;
  referenceAdvect(exact, p, &diagnostics);
  ASSERT_GT(diagnostics.margin, 1e-5) << "a finite-difference step would cross a switch point; pick another seed";
  if (p.scheme == AdvectionScheme::MacCormack) {
    EXPECT_GT(diagnostics.kept, 0);
    EXPECT_GT(diagnostics.reverted, 0);
  }

  const GpuCase gpu = upload(context(), input);
  std::vector<float> upstream;
  Tensor gradOut = randomTensor(context(), gpu.field.shape(), 42, -1.0f, 1.0f, &upstream);
  Tensor firstOrder(context(), gpu.field.shape());
  Tensor out(context(), gpu.field.shape());
  Tensor gradField = poisonedTensor(context(), gpu.field.shape());
  Tensor gradVelocity = poisonedTensor(context(), gpu.velocity.shape());
  Stream stream(context());
  physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, nullptr, p, out, &firstOrder);
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, p, gradOut, &firstOrder,
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

// Without a saved first-order pass the backward recomputes it and gives the same gradients.
TEST_P(AdvectTest, BackwardRecomputesFirstOrderPass) {
  const AdvectionCase<float> input = randomCase({5, 7, 5}, GetParam().mac, false, 51, 1.2f);
  const GpuCase gpu = upload(context(), input);
  Tensor gradOut = randomTensor(context(), gpu.field.shape(), 52);
  Tensor firstOrder(context(), gpu.field.shape());
  Tensor out(context(), gpu.field.shape());
  Tensor saved(context(), gpu.velocity.shape());
  Tensor recomputed = poisonedTensor(context(), gpu.velocity.shape());
  Stream stream(context());
  physics::advect(stream, gpu.flags, gpu.field, gpu.velocity, nullptr, params(), out, &firstOrder);
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, params(), gradOut, &firstOrder,
                          {.velocity = &saved});
  physics::advectBackward(stream, gpu.flags, gpu.field, gpu.velocity, params(), gradOut, nullptr,
                          {.velocity = &recomputed});
  stream.submit();
  EXPECT_TRUE(allClose(recomputed, saved.download(), {0, 0}));
}

INSTANTIATE_TEST_SUITE_P(Schemes, AdvectTest,
                         ::testing::Values(Variant{AdvectionScheme::SemiLagrangian, false},
                                           Variant{AdvectionScheme::MacCormack, false},
                                           Variant{AdvectionScheme::SemiLagrangian, true},
                                           Variant{AdvectionScheme::MacCormack, true}),
                         variantName);

TEST_F(GpuTest, AdvectRejectsMismatchedShapes) {
  const physics::GridSize grid{5, 6, 7};
  Tensor flags = physics::closedBoxFlagsTensor(context(), grid);
  Tensor field(context(), grid.volume());
  Tensor velocity(context(), {3, 7, 6, 4});
  Tensor out(context(), grid.volume());
  Stream stream(context());
  EXPECT_THROW(physics::advect(stream, flags, field, velocity, nullptr, {}, out), Error);
  Tensor thin(context(), {7, 6, 2});
  EXPECT_THROW(physics::advect(stream, physics::closedBoxFlagsTensor(context(), {2, 6, 7}), thin, thin, nullptr, {},
                               thin),
               Error);
}

}  // namespace
}  // namespace smokesvd::testing
