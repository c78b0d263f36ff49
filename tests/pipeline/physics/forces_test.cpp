#include <gtest/gtest.h>

#include "pipeline/physics/forces.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {

using ref::Field;

// Odd widths run the one-cell kernels, widths that are a multiple of 4 the block kernels.
class ForcesTest : public GpuTest, public ::testing::WithParamInterface<GridSize> {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    kGrid = GetParam();
    flagValues = ref::randomFlags(kGrid, 3);
    flags = Tensor::fromHost(context(), kGrid.volume(), flagValues);
    velocity = randomTensor(context(), kGrid.vector(), 4, -1, 1, &velocityValues);
  }
  ref::FlagView view() const { return ref::FlagView(kGrid, flagValues); }

  GridSize kGrid;
  std::vector<float> flagValues, velocityValues;
  Tensor flags, velocity;
};

TEST_P(ForcesTest, BuoyancyFromDensityTemperatureAndWind) {
  std::vector<float> density, temperature;
  Tensor tDensity = randomTensor(context(), kGrid.volume(), 5, 0, 1, &density);
  Tensor tTemperature = randomTensor(context(), kGrid.volume(), 6, 0, 2, &temperature);
  const physics::Buoyancy buoyancy{{0.01f, -0.02f, 0.03f}, {0.1f, 0.2f, -0.3f}, {-0.05f, 0.4f, 0.06f}};
  const float dt = 0.7f;
  Tensor out = poisonedTensor(context(), kGrid.vector());
  Tensor outNoTemperature = poisonedTensor(context(), kGrid.vector());
  Stream stream(context());
  physics::addBuoyancy(stream, flags, tDensity, &tTemperature, velocity, buoyancy, dt, out);
  physics::addBuoyancy(stream, flags, tDensity, nullptr, velocity, buoyancy, dt, outNoTemperature);
  stream.submit();
  auto widen3 = [](const glm::vec3& v) { return ref::Vec3d{v[0], v[1], v[2]}; };
  EXPECT_TRUE(allClose(out, ref::addBuoyancy(view(), ref::widen(density), ref::widen(temperature),
                                             ref::widen(velocityValues), widen3(buoyancy.uniform),
                                             widen3(buoyancy.perDensity), widen3(buoyancy.perTemperature), dt)));
  EXPECT_TRUE(allClose(outNoTemperature,
                       ref::addBuoyancy(view(), ref::widen(density), ref::widen(temperature), ref::widen(velocityValues),
                                        widen3(buoyancy.uniform), widen3(buoyancy.perDensity), {0, 0, 0}, dt)));
}

TEST_P(ForcesTest, CentredForceField) {
  std::vector<float> force;
  Tensor tForce = randomTensor(context(), kGrid.vector(), 7, -1, 1, &force);
  Tensor out = poisonedTensor(context(), kGrid.vector());
  Stream stream(context());
  physics::addForceField(stream, flags, tForce, velocity, 0.5f, out);
  stream.submit();
  EXPECT_TRUE(allClose(out, ref::addForceField(view(), ref::widen(force), ref::widen(velocityValues), 0.5)));
}

TEST_P(ForcesTest, VorticityAndConfinement) {
  const Shape vorticityShape{4, kGrid.z, kGrid.y, kGrid.x};
  Tensor vorticity = poisonedTensor(context(), vorticityShape);
  Tensor out = poisonedTensor(context(), kGrid.vector());
  Stream stream(context());
  physics::vorticityField(stream, velocity, vorticity);
  stream.submit();
  const Field expectedVorticity = ref::vorticityField(kGrid, ref::widen(velocityValues));
  EXPECT_TRUE(allClose(vorticity, expectedVorticity));

  Tensor force = poisonedTensor(context(), kGrid.vector());
  Stream confine(context());
  physics::vorticityForce(confine, vorticity, 0.3f, force);
  physics::addVorticityConfinement(confine, flags, vorticity, velocity, 0.3f, 0.9f, out);
  confine.submit();
  // The reference takes the GPU's vorticity, so that normalising a near-zero gradient cannot diverge.
  const Field gpuVorticity = ref::widen(vorticity.download());
  EXPECT_TRUE(allClose(force, ref::vorticityForce(kGrid, gpuVorticity, 0.3)));
  EXPECT_TRUE(allClose(out, ref::addVorticityConfinement(view(), gpuVorticity, ref::widen(velocityValues), 0.3, 0.9)));
}

std::string gridName(const ::testing::TestParamInfo<GridSize>& param) {
  return std::to_string(param.param.x) + "x" + std::to_string(param.param.y) + "x" + std::to_string(param.param.z);
}

INSTANTIATE_TEST_SUITE_P(Grids, ForcesTest,
                         ::testing::Values(GridSize{.x = 11, .y = 15, .z = 9}, GridSize{.x = 12, .y = 15, .z = 9}),
                         gridName);

}  // namespace
}  // namespace smokesvd::testing
