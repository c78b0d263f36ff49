// Volume metrics on the GPU against plain CPU references in double on random fields of an odd grid: density and
// velocity RMSE, the mean |MAC divergence| and the mean squared gradient norm of the cell-centred velocity.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/eval/volume_metrics.h"
#include "runtime/error.h"
#include "runtime/geometry.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/eval/metric_reference.h"

namespace smokesvd::testing {
namespace {

class VolumeMetricsTest : public GpuTest {};

TEST_F(VolumeMetricsTest, EveryMetricMatchesItsDoubleReference) {
  const GridSize grid{.x = 7, .y = 9, .z = 5};
  const double cells = 7 * 9 * 5;
  std::vector<float> a, b, u, w;
  const Tensor ta = randomTensor(context(), grid.volume(), 1, 0.0f, 2.0f, &a);
  const Tensor tb = randomTensor(context(), grid.volume(), 2, 0.0f, 2.0f, &b);
  const Tensor tu = randomTensor(context(), grid.vector(), 3, -1.0f, 1.0f, &u);
  const Tensor tw = randomTensor(context(), grid.vector(), 4, -1.0f, 1.0f, &w);

  double densitySquares = 0, velocitySquares = 0;
  for (std::size_t i = 0; i < a.size(); ++i) densitySquares += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
  for (std::size_t i = 0; i < u.size(); ++i) velocitySquares += (static_cast<double>(u[i]) - w[i]) * (static_cast<double>(u[i]) - w[i]);
  EXPECT_NEAR(eval::densityRmse(context(), ta, tb), std::sqrt(densitySquares / cells), 1e-5);
  EXPECT_NEAR(eval::velocityRmse(context(), tu, tw), std::sqrt(velocitySquares / cells), 1e-5);

  const eval::VelocityScores s = eval::velocityScores(context(), tu);
  EXPECT_NEAR(s.meanAbsDivergence, referenceMeanAbsDivergence(u, 7, 9, 5), 1e-5);
  EXPECT_NEAR(s.meanGradientSquared, referenceMeanGradientSquared(u, 7, 9, 5), 1e-5);
}

TEST_F(VolumeMetricsTest, ShapesMustAgree) {
  const Tensor a(context(), {5, 9, 7}), b(context(), {5, 9, 6}), u(context(), {3, 5, 9, 7});
  EXPECT_THROW(eval::densityRmse(context(), a, b), Error);
  EXPECT_THROW(eval::velocityRmse(context(), u, a), Error);
  EXPECT_THROW(eval::velocityScores(context(), a), Error);
}

}  // namespace
}  // namespace smokesvd::testing
