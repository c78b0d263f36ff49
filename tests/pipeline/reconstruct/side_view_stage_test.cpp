// The side-view stage's share of SvDiff-init's history-free estimate (SideViewOptions::initShare) on the tiny
// models: at 1 a frame's side view is SvDiff-init's estimate of it from its and the next front view, drawn with
// frame 0's noise (so that consecutive frames differ by their front views alone); in between it is the blend
// of that estimate and SvDiff's sample.
#include <gtest/gtest.h>

#include "pipeline/preset.h"
#include "pipeline/reconstruct/side_view_stage.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

class SideViewStageTest : public GpuTest {};

TEST_F(SideViewStageTest, InitShareBlendsSvDiffInitsHistoryFreeEstimateIn) {
  const Preset& p = preset("tiny");
  reconstruct::MethodModels models(context(), tinyModels(), p);
  const Shape image{1, 1, p.imageHeight, p.imageWidth};
  const auto pixels = static_cast<std::size_t>(p.imageHeight * p.imageWidth);
  const Tensor front = Tensor::fromHost(context(), image, randomValues(pixels, 31, 0.0f, 1.0f));
  const Tensor next = Tensor::fromHost(context(), image, randomValues(pixels, 32, 0.0f, 1.0f));
  reconstruct::FrameState state(context(), p);
  state.side1.upload(randomValues(pixels, 33, 0.0f, 1.0f));
  state.side2.upload(randomValues(pixels, 34, 0.0f, 1.0f));
  constexpr int kFrame = 5;
  reconstruct::SideViewOptions options;
  options.steps = 3;
  options.initSteps = 3;
  options.seed = 7;

  const std::vector<float> svdiff = reconstruct::sideView(context(), models, state, kFrame, front, next, options).download();
  // SvDiff-init's estimate of frame kFrame: what frame 0 gives for these front views, with frame 0's noise.
  reconstruct::FrameState fresh(context(), p);
  const std::vector<float> init = reconstruct::sideView(context(), models, fresh, 0, front, next, options).download();
  ASSERT_NE(svdiff, init);

  options.initShare = 1.0;
  EXPECT_EQ(reconstruct::sideView(context(), models, state, kFrame, front, next, options).download(), init);
  options.initShare = 0.25;
  const std::vector<float> blend = reconstruct::sideView(context(), models, state, kFrame, front, next, options).download();
  ASSERT_EQ(blend.size(), init.size());
  for (std::size_t i = 0; i < blend.size(); ++i) EXPECT_NEAR(blend[i], 0.75f * svdiff[i] + 0.25f * init[i], 1e-6f) << i;
  options.initShare = 1.5;
  EXPECT_THROW(reconstruct::sideView(context(), models, state, kFrame, front, next, options), Error);
}

}  // namespace
}  // namespace smokesvd::testing
