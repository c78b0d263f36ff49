#include <gtest/gtest.h>

#include "pipeline/physics/sources.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {

using physics::InflowMode;
using physics::SourceShape;
using physics::SourceState;

const GridSize kGrid{.x = 15, .y = 19, .z = 13};

std::vector<SourceState> testSources() {
  SourceState sphere;
  sphere.shape = SourceShape::Sphere;
  sphere.centre = {7.2f, 4.6f, 6.1f};
  sphere.size = {3.3f, 0, 0};
  sphere.density = 0.8f;
  sphere.temperature = 1.5f;
  sphere.noiseAmplitude = 0.4f;
  sphere.noiseScale = 2.5f;
  sphere.noiseSeed = 12345;
  sphere.noiseOffset = {0.3f, -4.7f, 1.1f};
  sphere.setsVelocity = true;
  sphere.velocity = {0.1f, 0.9f, -0.2f};
  SourceState box;
  box.shape = SourceShape::Box;
  box.centre = {4.5f, 12.3f, 5.0f};
  box.size = {2.2f, 1.4f, 3.1f};
  box.mode = InflowMode::Add;
  box.density = 0.5f;
  box.temperature = 0.25f;
  SourceState cylinder;
  cylinder.shape = SourceShape::Cylinder;
  cylinder.centre = {10.0f, 9.5f, 7.5f};
  cylinder.size = {2.4f, 3.6f, 0};
  cylinder.axis = {0.3f, 1.0f, 0.2f};
  cylinder.density = 1.2f;
  cylinder.setsVelocity = true;
  cylinder.velocity = {-0.5f, 0.3f, 0.7f};
  return {sphere, box, cylinder};
}

class SourcesTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    flagValues = ref::randomFlags(kGrid, 9, 0.1, 0.05);
    flags = Tensor::fromHost(context(), kGrid.volume(), flagValues);
  }
  std::vector<float> flagValues;
  Tensor flags;
};

TEST_F(SourcesTest, DensityAndTemperatureInflowOfEveryShapeAndMode) {
  std::vector<float> density, temperature;
  Tensor tDensity = randomTensor(context(), kGrid.volume(), 21, 0, 0.6f, &density);
  Tensor tTemperature = randomTensor(context(), kGrid.volume(), 22, 0, 0.6f, &temperature);
  const std::vector<SourceState> sources = testSources();
  physics::SourceTable table(context(), 4);
  table.write(sources);
  Tensor densityInflow = poisonedTensor(context(), kGrid.volume());
  Tensor temperatureInflow = poisonedTensor(context(), kGrid.volume());
  Tensor densityOnly = poisonedTensor(context(), kGrid.volume());
  Stream stream(context());
  physics::inflowFields(stream, flags, tDensity, &tTemperature, table, 0.5f, densityInflow, &temperatureInflow);
  physics::inflowFields(stream, flags, tDensity, nullptr, table, 0.5f, densityOnly, nullptr);
  stream.submit();
  ref::Field expectedDensity, expectedTemperature;
  ref::inflowFields(ref::FlagView(kGrid, flagValues), ref::widen(density), ref::widen(temperature), sources, 0.5,
                    expectedDensity, expectedTemperature);
  EXPECT_TRUE(allClose(densityInflow, expectedDensity));
  EXPECT_TRUE(allClose(temperatureInflow, expectedTemperature));
  EXPECT_TRUE(allClose(densityOnly, expectedDensity));
  EXPECT_GT(ref::maxAbs(expectedDensity), 0.5) << "the sources should cover fluid cells";
}

TEST_F(SourcesTest, VelocityBlendsOverCoveredFaces) {
  std::vector<float> velocity;
  Tensor tVelocity = randomTensor(context(), kGrid.vector(), 23, -1, 1, &velocity);
  const std::vector<SourceState> sources = testSources();
  physics::SourceTable table(context(), 3);
  table.write(sources);
  Stream stream(context());
  physics::applySourceVelocity(stream, flags, table, tVelocity);
  stream.submit();
  EXPECT_TRUE(allClose(tVelocity, ref::applySourceVelocity(ref::FlagView(kGrid, flagValues), sources, ref::widen(velocity))));
}

TEST_F(SourcesTest, ASmallSourceLeavesTheRestOfTheGridAlone) {
  SourceState small;
  small.centre = {3.2f, 4.7f, 9.1f};
  small.size = {1.6f, 0, 0};
  small.setsVelocity = true;
  small.velocity = {0.2f, 0.7f, 0.1f};
  const std::vector<SourceState> sources{small};
  physics::SourceTable table(context(), 1);
  table.write(sources);
  std::vector<float> density, velocity;
  Tensor tDensity = randomTensor(context(), kGrid.volume(), 25, 0, 0.5f, &density);
  Tensor tVelocity = randomTensor(context(), kGrid.vector(), 26, -1, 1, &velocity);
  Tensor inflow = poisonedTensor(context(), kGrid.volume());
  Stream stream(context());
  physics::inflowFields(stream, flags, tDensity, nullptr, table, 1.0f, inflow, nullptr);
  physics::applySourceVelocity(stream, flags, table, tVelocity);
  stream.submit();
  ref::Field expectedDensity, expectedTemperature;
  const ref::FlagView view(kGrid, flagValues);
  ref::inflowFields(view, ref::widen(density), ref::widen(density), sources, 1.0, expectedDensity, expectedTemperature);
  EXPECT_TRUE(allClose(inflow, expectedDensity));
  EXPECT_TRUE(allClose(tVelocity, ref::applySourceVelocity(view, sources, ref::widen(velocity))));
}

TEST_F(SourcesTest, AnEmptyTableAddsNothing) {
  Tensor density = randomTensor(context(), kGrid.volume(), 24, 0, 1);
  physics::SourceTable table(context(), 0);
  Tensor inflow = poisonedTensor(context(), kGrid.volume());
  Stream stream(context());
  physics::inflowFields(stream, flags, density, nullptr, table, 1.0f, inflow, nullptr);
  stream.submit();
  EXPECT_TRUE(allClose(inflow, std::vector<double>(static_cast<std::size_t>(kGrid.cells()), 0.0), {0, 0}));
}

TEST_F(SourcesTest, TooManySourcesIsAnError) {
  physics::SourceTable table(context(), 2);
  EXPECT_THROW(table.write(testSources()), Error);
}

}  // namespace
}  // namespace smokesvd::testing
