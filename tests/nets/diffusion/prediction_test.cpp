#include <gtest/gtest.h>

#include <cmath>

#include "nets/diffusion/forward_process.h"
#include "nets/diffusion/prediction.h"
#include "runtime/error.h"
#include "tests/harness/compare.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

using diffusion::NoiseSchedule;
using diffusion::Prediction;

class PredictionTest : public GpuTest {};

// For either prediction, the exact output (the target itself) implies the true noise and the true clean image,
// at a step with almost no noise, one in the middle and the last.
TEST_F(PredictionTest, TheTargetImpliesTheTrueNoiseAndCleanImage) {
  const NoiseSchedule schedule = NoiseSchedule::linear();
  const std::vector<int> steps{0, 250, 999};
  std::vector<float> clean, noise;
  const Var x0 = variable(randomTensor(context(), {3, 1, 5, 7}, 4, -1, 1, &clean));
  const Var eps = variable(randomTensor(context(), {3, 1, 5, 7}, 5, -2, 2, &noise));
  const diffusion::StepFactorTensors factors(context(), 3);
  factors.upload(diffusion::stepFactors(schedule, steps));
  for (const Prediction prediction : {Prediction::Noise, Prediction::Velocity}) {
    SCOPED_TRACE(diffusion::predictionName(prediction));
    Stream stream(context());
    Tape tape(stream);
    const Var noisy = diffusion::addNoise(tape, x0, eps, factors);
    const Var target = diffusion::predictionTarget(tape, prediction, x0, eps, factors);
    const Var impliedNoise = diffusion::noiseFromPrediction(tape, prediction, noisy, target, factors);
    const Var impliedClean = diffusion::cleanFromPrediction(tape, prediction, noisy, target, factors);
    stream.submit();
    EXPECT_TRUE(allClose(impliedNoise->value, noise, {2e-5, 1e-5}));
    // Epsilon's clean estimate divides by sqrt(abar) = 0.0064 at step 999, so x_s's rounding grows by 1 / 0.0064.
    EXPECT_TRUE(allClose(impliedClean->value, clean, {2e-4, 1e-4}));
    // v = sqrt(abar) eps - sqrt(1 - abar) x0, element by element.
    const std::vector<float> t = target->value.download();
    for (std::size_t i = 0; i < t.size(); ++i) {
      const int step = steps[i / 35];
      const double abar = schedule.alphaBar(step);
      const double expected =
          prediction == Prediction::Noise ? noise[i] : std::sqrt(abar) * noise[i] - std::sqrt(1 - abar) * clean[i];
      ASSERT_NEAR(t[i], expected, 1e-5) << "element " << i;
    }
  }
}

TEST_F(PredictionTest, NamesRoundTripAndAnUnknownNameIsAnError) {
  EXPECT_EQ(diffusion::predictionFromName("epsilon", "x"), Prediction::Noise);
  EXPECT_EQ(diffusion::predictionFromName("v", "x"), Prediction::Velocity);
  EXPECT_EQ(diffusion::predictionName(Prediction::Velocity), "v");
  try {
    diffusion::predictionFromName("x0", "svdiff.json [options]");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("svdiff.json [options]: 'prediction' must be \"epsilon\" or \"v\""), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace smokesvd::testing
