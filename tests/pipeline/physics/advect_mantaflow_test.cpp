// Agreement with mantaflow (tum-pbs/mantaflow v0.13, single precision) on one advection step of a
// 32x48x32 grid with closed walls: semi-Lagrangian and MacCormack density advection.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "nets/io/npy.h"
#include "pipeline/physics/advection.h"
#include "pipeline/physics/differential.h"
#include "pipeline/physics/grid.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/test_data.h"

namespace smokesvd::testing {
namespace {


class MantaflowAdvectionTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    arrays_ = io::readNpz(testData("mantaflow/advect_32x48x32.npz"));
  }
  Tensor tensor(const std::string& key) {
    const io::NpyArray& array = arrays_.at(key);
    return Tensor::fromHost(context(), array.shape, array.toFloat());
  }
  std::vector<float> values(const std::string& key) { return arrays_.at(key).toFloat(); }

  // The density advected by mantaflow's velocity with the given scheme.
  Tensor advected(physics::AdvectionScheme scheme) {
    Tensor density = tensor("density_in");
    Tensor interleaved = tensor("vel_mac");
    Stream stream(context());
    const physics::FlagGrid flags(stream, tensor("flags"));
    Tensor velocity(context(), flags.size().vector());
    Tensor out(context(), density.shape());
    physics::interleavedToPlanar(stream, interleaved, velocity);
    physics::advect(stream, flags, density, velocity, nullptr, {.scheme = scheme, .dt = 1.0f}, out);
    stream.submit();
    return out;
  }

  std::map<std::string, io::NpyArray> arrays_;
};

// vel_centered is mantaflow's getCentered of vel_mac: our MAC -> centred average, wherever both faces
// are stored. (On the last cell along a component's axis, a wall cell the advection never traces,
// the file repeats the last face; we count the missing face as 0.)
TEST_F(MantaflowAdvectionTest, CentredVelocityIsTheFaceAverage) {
  Stream stream(context());
  const GridSize grid = physics::volumeGrid(tensor("flags"), "flags");
  Tensor mac(context(), grid.vector()), centred(context(), grid.vector()), expected(context(), grid.vector());
  physics::interleavedToPlanar(stream, tensor("vel_mac"), mac);
  physics::interleavedToPlanar(stream, tensor("vel_centered"), expected);
  physics::macToCentred(stream, mac, centred);
  stream.submit();
  std::vector<float> actual = centred.download(), wanted = expected.download();
  const int64_t cells = grid.cells();
  const std::array<int64_t, 3> stride{1, grid.x, grid.x * grid.y}, size{grid.x, grid.y, grid.z};
  for (int64_t d = 0; d < 3; ++d)
    for (int64_t cell = 0; cell < cells; ++cell)
      if ((cell / stride[d]) % size[d] == size[d] - 1) actual[d * cells + cell] = wanted[d * cells + cell];
  EXPECT_TRUE(allClose(actual, wanted, grid.vector(), {1e-6, 1e-6}));
}

TEST_F(MantaflowAdvectionTest, SemiLagrangianMatchesMantaflow) {
  EXPECT_TRUE(allClose(advected(physics::AdvectionScheme::SemiLagrangian), values("density_sl"), {1e-6, 1e-6}));
}

TEST_F(MantaflowAdvectionTest, MacCormackMatchesMantaflow) {
  EXPECT_TRUE(allClose(advected(physics::AdvectionScheme::MacCormack), values("density_mc"), {1e-6, 1e-6}));
}

}  // namespace
}  // namespace smokesvd::testing
