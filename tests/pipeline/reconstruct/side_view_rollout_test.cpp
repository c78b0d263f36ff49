// SvDiff's autoregressive rollout (pipeline/reconstruct/side_view_rollout.h) on the tiny preset: a figure per
// frame beside the mirrored front view and the all-black floor, repeatable for a seed; and a synthesiser
// trained to predict v samples from pure noise through the same stage.
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/dataset/synthesised_side_views.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/reconstruct/side_view_rollout.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/train/training_run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

dataset::SceneDataset tinyData() {
  dataset::DatasetOptions options;
  options.validationEvery = 4;
  return dataset::SceneDataset(tinyDataset(), preset("tiny"), options);
}

// Few DDIM steps, so that a rollout of the tiny models takes seconds; `start` as SideViewOptions::start.
reconstruct::SideViewOptions fewSteps(int start) {
  reconstruct::SideViewOptions options;
  options.steps = 3;
  options.initSteps = 3;
  options.start = start;
  return options;
}

class SideViewRolloutTest : public GpuTest {};

TEST_F(SideViewRolloutTest, GivesEveryFrameBesideTheMirroredFrontViewAndTheBlackFloor) {
  const dataset::SceneDataset data = tinyData();
  reconstruct::MethodModels models(context(), tinyModels(), preset("tiny"));
  const reconstruct::SideViewOptions options = fewSteps(100);
  const reconstruct::RolloutResult a = reconstruct::sideViewRollout(context(), models, data, 0, 6, 1, options);
  ASSERT_EQ(a.scenes, 1);
  for (const auto* figures : {&a.psnr, &a.mirrored, &a.black}) {
    ASSERT_EQ(figures->size(), 6u);
    for (const double v : *figures) EXPECT_TRUE(std::isfinite(v) && v > 0) << v;
  }
  ASSERT_EQ(a.previous.size(), 5u);  // from frame 1
  for (const double v : a.previous) EXPECT_TRUE(std::isfinite(v) && v > 0) << v;
  // The front and side views of a scene differ, so the mirrored front view is not the side view; neither is black.
  EXPECT_LT(a.mirroredMean(), 100.0);
  EXPECT_LT(a.blackMean(), 100.0);
  const nlohmann::json json = a.toJson();
  for (const char* key : {"psnr_mean", "psnr_mirrored_front_mean", "psnr_black_mean", "psnr_first_10", "psnr_last_10",
                          "psnr_mirrored_front_first_10", "psnr_mirrored_front_last_10", "psnr_black_per_frame",
                          "psnr_previous_true_side_mean"})
    EXPECT_TRUE(json.contains(key)) << key;
  // A seed gives the same rollout.
  const reconstruct::RolloutResult b = reconstruct::sideViewRollout(context(), models, data, 0, 6, 1, options);
  EXPECT_EQ(a.psnr, b.psnr);
  // A rollout longer than every held-out scene is refused with the folder named.
  try {
    reconstruct::sideViewRollout(context(), models, data, 0, 9, 1, options);
    FAIL() << "a 9-frame rollout of 8-frame scenes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no validation scene has the 9 frames"), std::string::npos) << e.what();
  }
}

// A rollout of the training split keeps its side views (rollout.json, one .npy per scene) for NvRef's training; a
// rollout into the same folder reuses them instead of sampling again, and one that differs is refused.
TEST_F(SideViewRolloutTest, KeepsItsSideViewsAndReusesThem) {
  const dataset::SceneDataset data = tinyData();
  reconstruct::MethodModels models(context(), tinyModels(), preset("tiny"));
  const reconstruct::SideViewOptions options = fewSteps(100);
  const fs::path folder = tinyScratch("kept_side_views");
  reconstruct::RolloutScenes from;
  from.training = true;
  from.keepSideViews = folder;
  const reconstruct::RolloutResult a = reconstruct::sideViewRollout(context(), models, data, 0, 5, 2, options,
                                                                    reconstruct::RolloutHistory::Own, false, from);
  EXPECT_EQ(a.scenes, 2);
  const dataset::SynthesisedSideViews kept(folder, data);
  ASSERT_EQ(kept.training().size(), 2u);
  EXPECT_TRUE(kept.validation().empty());
  EXPECT_EQ(kept.training()[0].frames, 5);  // cut to the frames the rollout reached
  EXPECT_EQ(kept.side(kept.training()[0], 4).size(), static_cast<std::size_t>(preset("tiny").imageHeight * preset("tiny").imageWidth));
  // Rolled out again into the folder, the kept side views are this rollout's: black ones score the black floor.
  const reconstruct::RolloutResult again = reconstruct::sideViewRollout(context(), models, data, 0, 5, 2, options,
                                                                        reconstruct::RolloutHistory::Own, false, from);
  EXPECT_EQ(again.psnr, a.psnr);
  const dataset::SideViewRolloutManifest m = kept.manifest();
  dataset::writeSceneSideViews(folder, m, kept.training()[0],
                               std::vector<float>(static_cast<std::size_t>(m.frames * m.height * m.width), 0.0f));
  const reconstruct::RolloutResult black = reconstruct::sideViewRollout(context(), models, data, 0, 5, 1, options,
                                                                        reconstruct::RolloutHistory::Own, false, from);
  EXPECT_EQ(black.psnr, black.black);
  // Another rollout into the same folder is refused with the field that differs.
  try {
    reconstruct::SideViewOptions other = options;
    other.seed = 3;
    reconstruct::sideViewRollout(context(), models, data, 0, 5, 1, other, reconstruct::RolloutHistory::Own, false, from);
    FAIL() << "a rollout of another seed reused the folder";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'sampling' is"), std::string::npos) << e.what();
  }
}

// A rollout from a later frame covers the scene's frames from there: the baselines, which depend on the frame
// alone, are those frames' figures of a rollout from the start; one that would pass the scene's end is refused.
TEST_F(SideViewRolloutTest, FromALaterFrameCoversTheScenesFramesFromThere) {
  const dataset::SceneDataset data = tinyData();
  reconstruct::MethodModels models(context(), tinyModels(), preset("tiny"));
  const reconstruct::SideViewOptions options = fewSteps(100);
  const reconstruct::RolloutResult start = reconstruct::sideViewRollout(context(), models, data, 0, 6, 1, options);
  const reconstruct::RolloutResult later = reconstruct::sideViewRollout(context(), models, data, 2, 4, 1, options);
  ASSERT_EQ(later.psnr.size(), 4u);
  EXPECT_EQ(later.toJson().at("first_frame"), 2);
  for (std::size_t t = 0; t < 4; ++t) {
    EXPECT_EQ(later.mirrored[t], start.mirrored[t + 2]) << "frame " << t;
    EXPECT_EQ(later.black[t], start.black[t + 2]) << "frame " << t;
  }
  for (std::size_t t = 1; t < 4; ++t) EXPECT_EQ(later.previous[t - 1], start.previous[t + 1]) << "frame " << t;
  try {
    reconstruct::sideViewRollout(context(), models, data, 3, 6, 1, options);
    FAIL() << "a 6-frame rollout from frame 3 of 8-frame scenes was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no validation scene has the 9 frames of a rollout of 6 frames from frame 3"),
              std::string::npos)
        << e.what();
  }
}

// Teacher forcing: frames 0 and 1 come from SvDiff-init, which has no history, so they are the same as in
// the rollout on its own history; the later frames are conditioned on the true side views and differ.
TEST_F(SideViewRolloutTest, WithTrueHistoryOnlyTheFramesThatHaveHistoryChange) {
  const dataset::SceneDataset data = tinyData();
  reconstruct::MethodModels models(context(), tinyModels(), preset("tiny"));
  const reconstruct::SideViewOptions options = fewSteps(100);
  const reconstruct::RolloutResult own = reconstruct::sideViewRollout(context(), models, data, 0, 5, 1, options);
  const reconstruct::RolloutResult truth =
      reconstruct::sideViewRollout(context(), models, data, 0, 5, 1, options, reconstruct::RolloutHistory::Truth);
  EXPECT_FALSE(own.trueHistory);
  EXPECT_TRUE(truth.trueHistory);
  EXPECT_EQ(truth.toJson().at("history"), "truth");
  EXPECT_EQ(truth.psnr[0], own.psnr[0]);
  EXPECT_EQ(truth.psnr[1], own.psnr[1]);
  for (std::size_t t = 2; t < 5; ++t) EXPECT_NE(truth.psnr[t], own.psnr[t]) << "frame " << t;
  EXPECT_EQ(truth.mirrored, own.mirrored);
  EXPECT_EQ(truth.previous, own.previous);
}

// SvDiff and SvDiff-init trained with options.prediction "v" record it in their config, load as v-predicting
// synthesisers, and sample from pure noise (the side view of every frame a finite image).
TEST_F(SideViewRolloutTest, AVPredictingSynthesizerSamplesFromPureNoise) {
  const fs::path models = tinyScratch("rollout_v_models");
  for (const char* network : {"grho-coarse", "grho-fine", "nvref", "gu"})
    fs::copy(tinyModels() / network, models / network, fs::copy_options::recursive);
  const dataset::SceneDataset data = tinyData();
  for (const networks::Network n : {networks::Network::SvDiffInit, networks::Network::SvDiff}) {
    networks::NetworkConfig c = networks::defaultNetworkConfig("tiny", n);
    c.options["prediction"] = "v";
    c.train.steps = 3;
    c.train.warmup = 1;
    c.train.checkpointEvery = 3;
    c.train.validateEvery = 3;
    c.train.validationSamples = 1;
    c.data.validationEvery = 4;
    const auto trainer = train::makeTrainer(context(), c, data, models);
    train::TrainingOptions o;
    o.out = models / networks::networkName(n);
    o.quiet = true;
    train::runTraining(context(), *trainer, c, o);
    EXPECT_EQ(networks::readNetworkConfig(o.out / "config.json").options.value("prediction", ""), "v");
  }
  reconstruct::MethodModels loaded(context(), models, preset("tiny"));
  EXPECT_EQ(loaded.sideView->prediction(), diffusion::Prediction::Velocity);
  EXPECT_EQ(loaded.sideViewInit->prediction(), diffusion::Prediction::Velocity);
  const reconstruct::SideViewOptions options = fewSteps(-1);
  const reconstruct::RolloutResult r = reconstruct::sideViewRollout(context(), loaded, data, 0, 4, 1, options);
  for (const double v : r.psnr) EXPECT_TRUE(std::isfinite(v)) << v;
}

TEST_F(SideViewRolloutTest, AnUnknownPredictionIsAnErrorNamingTheConfig) {
  networks::NetworkConfig c = networks::defaultNetworkConfig("tiny", networks::Network::SvDiff);
  c.options["prediction"] = "x0";
  try {
    networks::diffusionSettings(c);
    FAIL() << "prediction x0 was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("[options]: 'prediction' must be \"epsilon\" or \"v\""), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace smokesvd::testing
