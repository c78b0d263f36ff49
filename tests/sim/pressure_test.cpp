#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pipeline/physics/pressure.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/sim/sim_reference.h"

namespace smokesvd::testing {
namespace {

namespace pressure_ops = physics::pressure_ops;
using namespace pressure_ops;
using physics::GridSize;
using ref::Field;
using ref::FlagView;

constexpr int kRz = 0, kAlpha = 1, kBeta = 2, kMaxR = 3, kMaxB = 4, kPap = 5, kMeanR = 6;  // pressure_scalars.glsl
const GridSize kGrid{13, 17, 11};

class PressureKernelTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    flagValues = ref::randomFlags(kGrid, 7);
    flags = Tensor::fromHost(context(), kGrid.volume(), flagValues);
    masks = Tensor(context(), kGrid.volume());
    Stream stream(context());
    stencilMasks(stream, flags, masks);
    stream.submit();
  }
  // A random volume that is 0 outside the fluid, as the solver's vectors are.
  Tensor fluidVolume(uint64_t seed, Field* values) {
    std::vector<float> v = randomValues(static_cast<std::size_t>(kGrid.cells()), seed);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (flagValues[i] != 1.0f) v[i] = 0.0f;
    *values = ref::widen(v);
    return Tensor::fromHost(context(), kGrid.volume(), v);
  }
  Tensor scalarBuffer(std::vector<float> values) {
    values.resize(kScalarSlots, 0.0f);
    return Tensor::fromHost(context(), {kScalarSlots}, values);
  }
  Tensor partials(int sets = 1) { return poisonedTensor(context(), {sets * partialCount(context(), kGrid)}); }
  FlagView view() const { return FlagView(kGrid, flagValues); }

  std::vector<float> flagValues;
  Tensor flags, masks;
};

TEST_F(PressureKernelTest, StencilMasksFromFlags) {
  Tensor out = poisonedTensor(context(), kGrid.volume());
  Stream stream(context());
  stencilMasks(stream, flags, out);
  stream.submit();
  EXPECT_TRUE(allClose(out, ref::stencilMasks(view()), {0, 0}));
}

TEST_F(PressureKernelTest, ResidualIsMinusDivergenceMinusLaplacian) {
  std::vector<float> velocityValues;
  Tensor velocity = randomTensor(context(), kGrid.vector(), 11, -1, 1, &velocityValues);
  Field pressureValues;
  Tensor pressure = fluidVolume(12, &pressureValues);
  Tensor residual = poisonedTensor(context(), kGrid.volume());
  Tensor partial = partials(3);
  Tensor scalars = scalarBuffer({});
  const int64_t fluidCells = std::count(flagValues.begin(), flagValues.end(), 1.0f);
  Stream stream(context());
  pressure_ops::residual(stream, masks, velocity, pressure, residual, partial);
  pressure_ops::scalars(stream, ScalarStep::Start, partial, partialCount(context(), kGrid), scalars, fluidCells);
  stream.submit();

  const Field div = ref::divergence(view(), ref::widen(velocityValues));
  const Field ap = ref::laplacian(view(), pressureValues);
  Field expected(div.size());
  Field b(div.size());
  for (std::size_t i = 0; i < div.size(); ++i) {
    b[i] = -div[i];
    expected[i] = -div[i] - ap[i];
  }
  EXPECT_TRUE(allClose(residual, expected));
  const std::vector<float> s = scalars.download();
  EXPECT_NEAR(s[kMaxB], ref::maxAbs(b), 1e-5);
  EXPECT_NEAR(s[kMaxR], ref::maxAbs(expected), 1e-5);
  double sum = 0;
  for (double v : expected) sum += v;
  EXPECT_NEAR(s[kMeanR], sum / static_cast<double>(fluidCells), 1e-5);
  EXPECT_EQ(s[kRz], 0.0f);
  EXPECT_EQ(s[kBeta], 0.0f);
}

TEST_F(PressureKernelTest, ApplyDirectionAndStepLength) {
  Field z, pOld;
  Tensor tz = fluidVolume(21, &z);
  Tensor tpOld = fluidVolume(22, &pOld);
  const double beta = 0.37, rz = 1.75;
  Tensor scalars = scalarBuffer({static_cast<float>(rz), 0, static_cast<float>(beta)});
  Tensor direction = poisonedTensor(context(), kGrid.volume());
  Tensor product = poisonedTensor(context(), kGrid.volume());
  Tensor partial = partials();
  Stream stream(context());
  applyDirection(stream, masks, tz, tpOld, scalars, direction, product, partial);
  pressure_ops::scalars(stream, ScalarStep::Step, partial, partialCount(context(), kGrid), scalars);
  stream.submit();

  Field p(z.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = flagValues[i] == 1.0f ? z[i] + beta * pOld[i] : 0.0;
  const Field q = ref::laplacian(view(), p);
  EXPECT_TRUE(allClose(direction, p));
  EXPECT_TRUE(allClose(product, q, {1e-5, 1e-5}));
  const double pq = ref::dot(p, q);
  const std::vector<float> s = scalars.download();
  EXPECT_NEAR(s[kPap], pq, 1e-5 * std::abs(pq) + 1e-5);
  EXPECT_NEAR(s[kAlpha], rz / pq, 1e-5 * std::abs(rz / pq));
}

TEST_F(PressureKernelTest, UpdateStepsAlongTheDirection) {
  std::vector<float> x, r, p, q;
  const Shape shape = kGrid.volume();
  Tensor tx = randomTensor(context(), shape, 31, -1, 1, &x);
  Tensor tr = randomTensor(context(), shape, 32, -1, 1, &r);
  Tensor tp = randomTensor(context(), shape, 33, -1, 1, &p);
  Tensor tq = randomTensor(context(), shape, 34, -1, 1, &q);
  const double alpha = -0.61;
  Tensor scalars = scalarBuffer({0, static_cast<float>(alpha)});
  Tensor xNew = poisonedTensor(context(), shape);
  Tensor rNew = poisonedTensor(context(), shape);
  Tensor partial = partials();
  Stream stream(context());
  update(stream, tx, tr, tp, tq, scalars, xNew, rNew, partial);
  pressure_ops::scalars(stream, ScalarStep::Residual, partial, partialCount(context(), kGrid), scalars);
  stream.submit();

  Field expectedX(x.size()), expectedR(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    expectedX[i] = x[i] + alpha * p[i];
    expectedR[i] = r[i] - alpha * q[i];
  }
  EXPECT_TRUE(allClose(xNew, expectedX));
  EXPECT_TRUE(allClose(rNew, expectedR));
  EXPECT_NEAR(scalars.download()[kMaxR], ref::maxAbs(expectedR), 1e-6);
}

TEST_F(PressureKernelTest, MeanRemoval) {
  Field r;
  Tensor tr = fluidVolume(81, &r);
  const double mean = 0.123;
  Tensor scalars = scalarBuffer({0, 0, 0, 0, 0, 0, static_cast<float>(mean)});
  Tensor out = poisonedTensor(context(), kGrid.volume());
  Tensor partial = partials();
  Stream stream(context());
  removeMean(stream, masks, tr, scalars, out, partial);
  pressure_ops::scalars(stream, ScalarStep::Residual, partial, partialCount(context(), kGrid), scalars);
  stream.submit();
  Field expected(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) expected[i] = flagValues[i] == 1.0f ? r[i] - mean : 0.0;
  EXPECT_TRUE(allClose(out, expected));
  EXPECT_NEAR(scalars.download()[kMaxR], ref::maxAbs(expected), 1e-6);
}

TEST_F(PressureKernelTest, DirectionScalarsFromPartials) {
  const int64_t n = 301;
  std::vector<float> values;
  Tensor partial = randomTensor(context(), {n}, 41, -1, 1, &values);
  const double rzOld = 2.5;
  Tensor scalars = scalarBuffer({static_cast<float>(rzOld)});
  Stream stream(context());
  pressure_ops::scalars(stream, ScalarStep::Direction, partial, n, scalars);
  stream.submit();
  double sum = 0;
  for (float v : values) sum += v;
  const std::vector<float> s = scalars.download();
  EXPECT_NEAR(s[kRz], sum, 1e-5);
  EXPECT_NEAR(s[kBeta], sum / rzOld, 1e-5);
}

TEST_F(PressureKernelTest, JacobiSweepsInEveryMode) {
  Field rhs, x;
  Tensor trhs = fluidVolume(51, &rhs);
  Tensor tx = fluidVolume(52, &x);
  const GridSize coarseGrid = coarserGrid(kGrid);
  std::vector<float> coarseValues;
  Tensor coarse = randomTensor(context(), coarseGrid.volume(), 53, -1, 1, &coarseValues);
  const float weight = 0.8f;
  const Field zero(x.size(), 0.0);
  const Field corrected = ref::prolongAdd(view(), x, ref::widen(coarseValues), coarseGrid);
  struct Case {
    SmoothMode mode;
    Field start;
  };
  for (const Case& c : {Case{SmoothMode::First, zero}, Case{SmoothMode::Plain, x}, Case{SmoothMode::Corrected, corrected}}) {
    Tensor xNew = poisonedTensor(context(), kGrid.volume());
    Tensor partial = partials();
    Tensor scalars = scalarBuffer({});
    Stream stream(context());
    smooth(stream, c.mode, true, masks, trhs, tx, coarse, coarseGrid, weight, xNew, partial);
    pressure_ops::scalars(stream, ScalarStep::Direction, partial, partialCount(context(), kGrid), scalars);
    stream.submit();
    const Field expected = ref::jacobiSweep(view(), rhs, c.start, weight);
    EXPECT_TRUE(allClose(xNew, expected)) << "mode " << static_cast<int>(c.mode);
    EXPECT_NEAR(scalars.download()[kRz], ref::dot(rhs, expected), 1e-5);
  }
}

TEST_F(PressureKernelTest, RestrictionAndCoarseFlags) {
  Field rhs, x;
  Tensor trhs = fluidVolume(61, &rhs);
  Tensor tx = fluidVolume(62, &x);
  const GridSize coarseGrid = coarserGrid(kGrid);
  Tensor coarseFlags = poisonedTensor(context(), coarseGrid.volume());
  Tensor coarseMasks = poisonedTensor(context(), coarseGrid.volume());
  Tensor coarseRhs = poisonedTensor(context(), coarseGrid.volume());
  Stream stream(context());
  coarsenFlags(stream, flags, coarseFlags);
  stencilMasks(stream, coarseFlags, coarseMasks);
  restrictResidual(stream, masks, trhs, tx, coarseMasks, 0.5f, coarseRhs);
  stream.submit();
  const std::vector<float> expectedFlags = ref::coarsenFlags(view(), coarseGrid);
  EXPECT_TRUE(allClose(coarseFlags, expectedFlags, {0, 0}));
  EXPECT_TRUE(allClose(coarseRhs, ref::restrictResidual(view(), rhs, x, FlagView(coarseGrid, expectedFlags), 0.5),
                       {1e-5, 1e-5}));
}

TEST_F(PressureKernelTest, VelocityCorrection) {
  std::vector<float> velocityValues;
  Tensor velocity = randomTensor(context(), kGrid.vector(), 71, -1, 1, &velocityValues);
  Field pressureValues;
  Tensor pressure = fluidVolume(72, &pressureValues);
  Tensor out = poisonedTensor(context(), kGrid.vector());
  Stream stream(context());
  correctVelocity(stream, masks, pressure, velocity, out);
  stream.submit();
  EXPECT_TRUE(allClose(out, ref::correctVelocity(view(), pressureValues, ref::widen(velocityValues))));
}

}  // namespace
}  // namespace smokesvd::testing
