// Mass of a smoke blob under semi-Lagrangian advection with closed walls.
//
// SL resamples the field at back-traced points x − v(x)·dt. Its mass change is Σ_y ρ(y)·(W(y) − 1),
// with W(y) the total trilinear weight source cell y hands out.
//  - Uniform flow: every target has the same fractional weights, so W(y) = (w0 + w1)³ = 1 for every
//    source cell whose receiving targets are all interior: mass is conserved exactly up to float
//    rounding while the blob stays clear of the walls. Bound: |ΔM|/M ≤ 1e-6 (measured 1.4e-8).
//  - Solid rotation at ω radians per step (divergence-free, also discretely): the back-trace
//    x ↦ x − v(x)·dt is linear with Jacobian determinant 1 + ω²dt², so the resampled mass is
//    M / (1 + ω²dt²) (SL is only first-order in time; the shrinkage is its error). Trilinear
//    interpolation of a smooth blob adds an O(h²) smoothing that leaves mass unchanged to leading
//    order. Bound: |M_out/M − 1/(1 + ω²dt²)| ≤ 2e-4 (ω = 0.15: 0.9780 expected, 4e-5 off).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numeric>

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

const GridSize kGrid{.x = 31, .y = 29, .z = 33};

double total(const std::vector<float>& values) { return std::accumulate(values.begin(), values.end(), 0.0); }

// A smooth blob of compact support (radius 7 cells) near the grid's centre.
std::vector<float> blob() {
  std::vector<float> density(static_cast<std::size_t>(kGrid.cells()));
  std::size_t index = 0;
  for (int k = 0; k < kGrid.z; ++k)
    for (int j = 0; j < kGrid.y; ++j)
      for (int i = 0; i < kGrid.x; ++i) {
        const double dx = i + 0.5 - 15.2, dy = j + 0.5 - 14.1, dz = k + 0.5 - 16.7;
        const double r2 = (dx * dx + dy * dy + dz * dz) / 49.0;
        density[index++] = r2 < 1.0 ? static_cast<float>((1.0 - r2) * (1.0 - r2)) : 0.0f;
      }
  return density;
}

// MAC velocity [3, D, H, W] sampled from v(x, y, z) at the face positions.
template <typename Field>
std::vector<float> macVelocity(Field field) {
  std::vector<float> velocity(static_cast<std::size_t>(3 * kGrid.cells()));
  for (int c = 0; c < 3; ++c) {
    std::size_t index = static_cast<std::size_t>(c * kGrid.cells());
    for (int k = 0; k < kGrid.z; ++k)
      for (int j = 0; j < kGrid.y; ++j)
        for (int i = 0; i < kGrid.x; ++i) {
          double position[3] = {i + 0.5, j + 0.5, k + 0.5};
          position[c] -= 0.5;
          velocity[index++] = static_cast<float>(field(position)[c]);
        }
  }
  return velocity;
}

class AdvectMassTest : public GpuTest {
 protected:
  double massRatio(const std::vector<float>& velocity, float dt) {
    const std::vector<float> density = blob();
    Stream stream(context());
    const physics::FlagGrid flags(stream, physics::closedBoxFlagsTensor(context(), kGrid));
    Tensor field = Tensor::fromHost(context(), kGrid.volume(), density);
    Tensor mac = Tensor::fromHost(context(), kGrid.vector(), velocity);
    Tensor out(context(), kGrid.volume());
    physics::advect(stream, flags, field, mac, nullptr, {.scheme = physics::AdvectionScheme::SemiLagrangian, .dt = dt},
                    out);
    stream.submit();
    return total(out.download()) / total(density);
  }
};

TEST_F(AdvectMassTest, UniformFlowConservesMass) {
  const std::vector<float> velocity = macVelocity([](const double*) {
    return std::array<double, 3>{0.37, -0.61, 1.23};
  });
  EXPECT_NEAR(massRatio(velocity, 1.0f), 1.0, 1e-6);
}

TEST_F(AdvectMassTest, SolidRotationScalesMassByTheTraceJacobian) {
  const double omega = 0.15;
  const float dt = 1.0f;
  const std::vector<float> velocity = macVelocity([omega](const double* p) {
    return std::array<double, 3>{-omega * (p[2] - 16.5), 0.0, omega * (p[0] - 15.5)};
  });
  EXPECT_NEAR(massRatio(velocity, dt), 1.0 / (1.0 + omega * omega * dt * dt), 2e-4);
}

}  // namespace
}  // namespace smokesvd::testing
