#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pipeline/physics/pressure.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/physics/sim_reference.h"

namespace smokesvd::testing {
namespace {

namespace pressure_ops = physics::pressure_ops;
using namespace pressure_ops;
using ref::Field;
using ref::FlagView;

constexpr int kRz = 0, kAlpha = 1, kBeta = 2, kMaxR = 3, kMaxB = 4, kPap = 5, kMeanR = 6;  // pressure_scalars.glsl

// Real [D, H, W] values into the solver's padded layout [D, H, P] (0 in the padding).
template <typename T>
std::vector<T> padded(const GridSize& grid, const std::vector<T>& values) {
  const int64_t width = paddedGrid(grid).x;
  std::vector<T> result(static_cast<std::size_t>(width * grid.y * grid.z), T{});
  for (int64_t row = 0; row < grid.y * grid.z; ++row)
    std::copy_n(values.begin() + row * grid.x, grid.x, result.begin() + row * width);
  return result;
}
// Odd widths use the padded layout and the one-cell kernels at its edges; widths that are a multiple of 4
// run block kernels throughout.
class PressureKernelTest : public GpuTest, public ::testing::WithParamInterface<GridSize> {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    kGrid = GetParam();
    flagValues = ref::randomFlags(kGrid, 7);
    flags = Tensor::fromHost(context(), kGrid.volume(), flagValues);
    masks = Tensor(context(), paddedGrid(kGrid).volume());
    Stream stream(context());
    stencilMasks(stream, flags, masks);
    stream.submit();
  }
  // A random padded volume that is 0 outside the fluid, as the solver's vectors are; `values` gets the
  // real-layout values.
  Tensor fluidVolume(uint64_t seed, Field* values) { return fluidVolume(seed, values, kGrid, flagValues); }
  Tensor fluidVolume(uint64_t seed, Field* values, const GridSize& grid, const std::vector<float>& f) {
    std::vector<float> v = randomValues(static_cast<std::size_t>(grid.cells()), seed);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (f[i] != 1.0f) v[i] = 0.0f;
    *values = ref::widen(v);
    return Tensor::fromHost(context(), paddedGrid(grid).volume(), padded(grid, v));
  }
  Tensor scalarBuffer(std::vector<float> values) {
    values.resize(kScalarSlots, 0.0f);
    return Tensor::fromHost(context(), {kScalarSlots}, values);
  }
  Tensor partials() { return poisonedTensor(context(), {3 * std::max(startPartialCount(context(), kGrid), partialCount(context(), kGrid))}); }
  Tensor paddedPoison() { return poisonedTensor(context(), paddedGrid(kGrid).volume()); }
  FlagView view() const { return FlagView(kGrid, flagValues); }
  // Compares a padded result with a real-layout reference; the padding must hold zeros.
  ::testing::AssertionResult matches(const Tensor& actual, const Field& expected, Tolerance tolerance = {}) {
    std::vector<double> full(expected.begin(), expected.end());
    return allClose(actual, padded(kGrid, full), tolerance);
  }

  GridSize kGrid;
  std::vector<float> flagValues;
  Tensor flags, masks;
};

TEST_P(PressureKernelTest, StencilMasksFromFlags) {
  Tensor out = paddedPoison();
  Stream stream(context());
  stencilMasks(stream, flags, out);
  stream.submit();
  const std::vector<float> expected = ref::stencilMasks(view());
  EXPECT_TRUE(matches(out, ref::widen(expected), {0, 0}));
}

TEST_P(PressureKernelTest, ResidualIsMinusDivergenceMinusLaplacian) {
  std::vector<float> velocityValues;
  Tensor velocity = randomTensor(context(), kGrid.vector(), 11, -1, 1, &velocityValues);
  Field pressureValues;
  Tensor pressure = fluidVolume(12, &pressureValues);
  // The kernel writes the real cells only; the padding of a residual buffer is kept at 0.
  Tensor residual = Tensor::fromHost(context(), paddedGrid(kGrid).volume(),
                                     padded(kGrid, std::vector<float>(static_cast<std::size_t>(kGrid.cells()), NAN)));
  Tensor partial = partials();
  Tensor scalars = scalarBuffer({});
  const int64_t fluidCells = std::count(flagValues.begin(), flagValues.end(), 1.0f);
  Stream stream(context());
  pressure_ops::residual(stream, masks, velocity, pressure, residual, partial);
  pressure_ops::scalars(stream, ScalarStep::Start, partial, startPartialCount(context(), kGrid), scalars, fluidCells);
  stream.submit();

  const Field div = ref::divergence(view(), ref::widen(velocityValues));
  const Field ap = ref::laplacian(view(), pressureValues);
  Field expected(div.size()), b(div.size());
  for (std::size_t i = 0; i < div.size(); ++i) {
    b[i] = -div[i];
    expected[i] = -div[i] - ap[i];
  }
  EXPECT_TRUE(matches(residual, expected));
  const std::vector<float> s = scalars.download();
  EXPECT_NEAR(s[kMaxB], ref::maxAbs(b), 1e-5);
  EXPECT_NEAR(s[kMaxR], ref::maxAbs(expected), 1e-5);
  double sum = 0;
  for (double v : expected) sum += v;
  EXPECT_NEAR(s[kMeanR], sum / static_cast<double>(fluidCells), 1e-5);
  EXPECT_EQ(s[kRz], 0.0f);
  EXPECT_EQ(s[kBeta], 0.0f);
}

TEST_P(PressureKernelTest, ApplyDirectionAndStepLength) {
  Field z, pOld;
  Tensor tz = fluidVolume(21, &z);
  Tensor tpOld = fluidVolume(22, &pOld);
  const double beta = 0.37, rz = 1.75;
  Tensor scalars = scalarBuffer({static_cast<float>(rz), 0, static_cast<float>(beta)});
  Tensor direction = paddedPoison(), product = paddedPoison();
  Tensor partial = partials();
  Stream stream(context());
  applyDirection(stream, masks, tz, tpOld, scalars, direction, product, partial);
  pressure_ops::scalars(stream, ScalarStep::Step, partial, partialCount(context(), kGrid), scalars);
  stream.submit();

  Field p(z.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = z[i] + beta * pOld[i];
  const Field q = ref::laplacian(view(), p);
  EXPECT_TRUE(matches(direction, p));
  EXPECT_TRUE(matches(product, q, {1e-5, 1e-5}));
  const double pq = ref::dot(p, q);
  const std::vector<float> s = scalars.download();
  EXPECT_NEAR(s[kPap], pq, 1e-5 * std::abs(pq) + 1e-5);
  EXPECT_NEAR(s[kAlpha], rz / pq, 1e-5 * std::abs(rz / pq));
}

TEST_P(PressureKernelTest, UpdateStepsAlongTheDirection) {
  Field x, r, p, q;
  Tensor tx = fluidVolume(31, &x), tr = fluidVolume(32, &r), tp = fluidVolume(33, &p), tq = fluidVolume(34, &q);
  const double alpha = -0.61;
  Tensor scalars = scalarBuffer({0, static_cast<float>(alpha)});
  Tensor xNew = paddedPoison(), rNew = paddedPoison();
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
  EXPECT_TRUE(matches(xNew, expectedX));
  EXPECT_TRUE(matches(rNew, expectedR));
  EXPECT_NEAR(scalars.download()[kMaxR], ref::maxAbs(expectedR), 1e-6);
}

TEST_P(PressureKernelTest, MeanRemoval) {
  Field r;
  Tensor tr = fluidVolume(81, &r);
  const double mean = 0.123;
  Tensor scalars = scalarBuffer({0, 0, 0, 0, 0, 0, static_cast<float>(mean)});
  Tensor out = paddedPoison();
  Tensor partial = partials();
  Stream stream(context());
  removeMean(stream, masks, tr, scalars, out, partial);
  pressure_ops::scalars(stream, ScalarStep::Residual, partial, partialCount(context(), kGrid), scalars);
  stream.submit();
  Field expected(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) expected[i] = flagValues[i] == 1.0f ? r[i] - mean : 0.0;
  EXPECT_TRUE(matches(out, expected));
  EXPECT_NEAR(scalars.download()[kMaxR], ref::maxAbs(expected), 1e-6);
}

TEST_P(PressureKernelTest, DirectionScalarsFromPartials) {
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

TEST_P(PressureKernelTest, JacobiSweepsFromZeroAndFromAGuess) {
  Field rhs, x;
  Tensor trhs = fluidVolume(51, &rhs);
  Tensor tx = fluidVolume(52, &x);
  const float weight = 0.8f;
  for (bool first : {true, false}) {
    Tensor xNew = paddedPoison();
    Tensor partial = partials();
    Tensor scalars = scalarBuffer({});
    Stream stream(context());
    smooth(stream, first, true, masks, trhs, tx, weight, xNew, partial);
    pressure_ops::scalars(stream, ScalarStep::Direction, partial, partialCount(context(), kGrid), scalars);
    stream.submit();
    const Field expected = ref::jacobiSweep(view(), rhs, first ? Field(x.size(), 0.0) : x, weight);
    EXPECT_TRUE(matches(xNew, expected)) << (first ? "first sweep" : "sweep");
    EXPECT_NEAR(scalars.download()[kRz], ref::dot(rhs, expected), 1e-5);
  }
}

TEST_P(PressureKernelTest, ResidualRestrictionProlongationAndCoarseFlags) {
  Field rhs, x;
  Tensor trhs = fluidVolume(61, &rhs);
  Tensor tx = fluidVolume(62, &x);
  const GridSize coarseGrid = coarserGrid(kGrid);
  Tensor coarseFlags = poisonedTensor(context(), coarseGrid.volume());
  Tensor coarseMasks = poisonedTensor(context(), paddedGrid(coarseGrid).volume());
  Tensor levelResidualOut = paddedPoison();
  Tensor coarseRhs = poisonedTensor(context(), paddedGrid(coarseGrid).volume());
  Stream stream(context());
  coarsenFlags(stream, flags, coarseFlags);
  stencilMasks(stream, coarseFlags, coarseMasks);
  levelResidual(stream, masks, trhs, tx, levelResidualOut);
  restrictResidual(stream, levelResidualOut, coarseMasks, 0.5f, coarseRhs);
  stream.submit();
  const std::vector<float> expectedFlags = ref::coarsenFlags(view(), coarseGrid);
  EXPECT_TRUE(allClose(coarseFlags, expectedFlags, {0, 0}));
  const Field ax = ref::laplacian(view(), x);
  Field residual(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) residual[i] = flagValues[i] == 1.0f ? rhs[i] - ax[i] : 0.0;
  EXPECT_TRUE(matches(levelResidualOut, residual, {1e-5, 1e-5}));
  const Field expectedCoarse = ref::restrictResidual(view(), rhs, x, FlagView(coarseGrid, expectedFlags), 0.5);
  std::vector<double> coarsePadded(expectedCoarse.begin(), expectedCoarse.end());
  EXPECT_TRUE(allClose(coarseRhs, padded(coarseGrid, coarsePadded), {1e-5, 1e-5}));

  Field coarseValues;
  Tensor coarse = fluidVolume(63, &coarseValues, coarseGrid, expectedFlags);
  Tensor prolonged = paddedPoison();
  Stream correct(context());
  prolong(correct, masks, tx, coarse, prolonged);
  correct.submit();
  EXPECT_TRUE(matches(prolonged, ref::prolongAdd(view(), x, coarseValues, coarseGrid)));
}

TEST_P(PressureKernelTest, VelocityCorrection) {
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

TEST_P(PressureKernelTest, SolverPressureRoundTripsThroughItsPaddedLayout) {
  physics::PressureSolver solver(context(), flags);
  std::vector<float> values = randomValues(static_cast<std::size_t>(kGrid.cells()), 91);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (flagValues[i] != 1.0f) values[i] = 0.0f;
  solver.setPressure(values);
  EXPECT_EQ(solver.pressure(), values);
}

std::string gridName(const ::testing::TestParamInfo<GridSize>& param) {
  return std::to_string(param.param.x) + "x" + std::to_string(param.param.y) + "x" + std::to_string(param.param.z);
}

INSTANTIATE_TEST_SUITE_P(Grids, PressureKernelTest,
                         ::testing::Values(GridSize{.x = 13, .y = 17, .z = 11}, GridSize{.x = 16, .y = 15, .z = 9}),
                         gridName);

}  // namespace
}  // namespace smokesvd::testing
