// The forces through `smokesvd op`, as a user checking them against mantaflow would run them: each
// against the CPU reference, and an upstream gradient (they have no backward) as a clear error.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/harness/compare.h"
#include "tests/harness/op_runner.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {


const GridSize kGrid{.x = 8, .y = 11, .z = 7};

std::vector<float> wave(std::size_t count, double phase) {
  std::vector<float> values(count);
  for (std::size_t i = 0; i < count; ++i) values[i] = static_cast<float>(std::sin(0.61 * static_cast<double>(i) + phase));
  return values;
}

class ForcesCommand : public ::testing::Test {
 protected:
  const std::vector<float> flags = ref::randomFlags(kGrid, 9);
  const std::vector<float> velocity = wave(static_cast<std::size_t>(3 * kGrid.cells()), 0.3);
  const ref::FlagView view{kGrid, flags};
  io::NpyArray velocityArray() const { return io::NpyArray::fromFloats(kGrid.vector(), velocity); }
  io::NpyArray flagArray() const { return io::NpyArray::fromFloats(kGrid.volume(), flags); }
};

TEST_F(ForcesCommand, Buoyancy) {
  const std::vector<float> density = wave(static_cast<std::size_t>(kGrid.cells()), 1.1);
  const OpRun run = runOpCommand("buoyancy",
                                 {{"velocity", velocityArray()},
                                  {"density", io::NpyArray::fromFloats(kGrid.volume(), density)},
                                  {"flags", flagArray()}},
                                 {"out"}, {"uniform=0.01,0,-0.02", "per_density=0,0.3,0", "dt=0.5"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const ref::Field expected = ref::addBuoyancy(view, ref::widen(density), ref::Field(density.size(), 0.0),
                                               ref::widen(velocity), {0.01, 0, -0.02}, {0, 0.3, 0}, {0, 0, 0}, 0.5);
  EXPECT_TRUE(allClose(run.outputs.at("out").floats, expected, kGrid.vector()));
}

TEST_F(ForcesCommand, ForceField) {
  const std::vector<float> force = wave(static_cast<std::size_t>(3 * kGrid.cells()), 2.0);
  const OpRun run = runOpCommand("force_field",
                                 {{"velocity", velocityArray()},
                                  {"force", io::NpyArray::fromFloats(kGrid.vector(), force)},
                                  {"flags", flagArray()}},
                                 {"out"}, {"dt=0.25"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_TRUE(allClose(run.outputs.at("out").floats,
                       ref::addForceField(view, ref::widen(force), ref::widen(velocity), 0.25), kGrid.vector()));
}

TEST_F(ForcesCommand, VorticityConfinement) {
  const OpRun run = runOpCommand("vorticity_confinement", {{"velocity", velocityArray()}, {"flags", flagArray()}},
                                 {"out"}, {"strength=0.2", "dt=0.8"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const ref::Field vorticity = ref::vorticityField(kGrid, ref::widen(velocity));
  EXPECT_TRUE(allClose(run.outputs.at("out").floats,
                       ref::addVorticityConfinement(view, vorticity, ref::widen(velocity), 0.2, 0.8), kGrid.vector(),
                       {1e-5, 1e-4}));
}

TEST_F(ForcesCommand, UpstreamGradientIsAnError) {
  const OpRun run = runOpCommand("vorticity_confinement",
                                 {{"velocity", velocityArray()}, {"grad_out", velocityArray()}}, {"out", "grad_velocity"});
  EXPECT_NE(run.exitCode, 0);
  EXPECT_NE(run.err.find("no backward pass"), std::string::npos) << run.err;
}

TEST_F(ForcesCommand, MalformedVectorAttributeIsAnError) {
  const OpRun run = runOpCommand("buoyancy",
                                 {{"velocity", velocityArray()},
                                  {"density", io::NpyArray::fromFloats(kGrid.volume(), std::vector<float>(kGrid.cells()))}},
                                 {"out"}, {"per_density=0,1"});
  EXPECT_NE(run.exitCode, 0);
  EXPECT_NE(run.err.find("per_density"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace smokesvd::testing
