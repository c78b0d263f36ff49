// Agreement with mantaflow (tum-pbs/mantaflow v0.13, single precision) on one advection step of a
// 32x48x32 grid with closed walls: semi-Lagrangian and MacCormack density advection.
#include <gtest/gtest.h>

#include <string>

#include "nets/io/npy.h"
#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"

namespace smokesvd::testing {
namespace {

const char* const kReference = SMOKESVD_SOURCE_DIR "/../shared/testdata/mantaflow/advect_32x48x32.npz";

class MantaflowAdvectionTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    arrays_ = io::readNpz(kReference);
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

TEST_F(MantaflowAdvectionTest, SemiLagrangianMatchesMantaflow) {
  EXPECT_TRUE(allClose(advected(physics::AdvectionScheme::SemiLagrangian), values("density_sl"), {1e-6, 1e-6}));
}

TEST_F(MantaflowAdvectionTest, MacCormackMatchesMantaflow) {
  EXPECT_TRUE(allClose(advected(physics::AdvectionScheme::MacCormack), values("density_mc"), {1e-6, 1e-6}));
}

}  // namespace
}  // namespace smokesvd::testing
