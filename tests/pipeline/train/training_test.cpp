// The trainers and the training loop on the tiny preset: every network trains from a dataset the test
// simulates, a killed-and-resumed run ends with exactly the weights of an uninterrupted one, the same
// seed gives the same weights, and bad inputs are clear errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "nets/io/safetensors.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/dataset/synthesised_side_views.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/train/training_run.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) { return tinyScratch("training_" + name); }

const fs::path& tinyData() { return tinyDataset(); }

// The tiny scenes split as tinyConfig's data section splits them: every 4th held out.
dataset::SceneDataset tinySplit() {
  dataset::DatasetOptions options;
  options.validationEvery = 4;
  return dataset::SceneDataset(tinyData(), preset("tiny"), options);
}

networks::NetworkConfig tinyConfig(networks::Network network, int64_t steps) {
  networks::NetworkConfig c = networks::defaultNetworkConfig("tiny", network);
  c.train.steps = steps;
  c.train.warmup = 1;
  c.train.logEvery = 1;
  c.train.checkpointEvery = 3;
  c.train.validateEvery = steps;
  c.train.validationSamples = 2;
  c.data.validationEvery = 4;
  if (network == networks::Network::Gu) c.options["finetune_steps"] = 2;
  return c;
}

train::TrainingResult trainTiny(const networks::NetworkConfig& config, const fs::path& out, int64_t stopAfter = -1,
                                bool resume = false, const fs::path& models = {}) {
  const dataset::SceneDataset data = tinySplit();
  const auto trainer = train::makeTrainer(testContext(), config, data, models.empty() ? out.parent_path() : models);
  train::TrainingOptions o;
  o.out = out;
  o.resume = resume;
  o.stopAfter = stopAfter;
  o.quiet = true;
  o.seed = 7;
  return train::runTraining(testContext(), *trainer, config, o);
}

train::TrainingResult trainTiny(networks::Network network, const fs::path& out, int64_t steps, int64_t stopAfter = -1,
                                bool resume = false, const fs::path& models = {}) {
  return trainTiny(tinyConfig(network, steps), out, stopAfter, resume, models);
}

std::vector<io::NamedArray> weightsOf(const fs::path& run) { return io::readSafetensors(run / "model.safetensors").tensors; }

void expectSameWeights(const fs::path& a, const fs::path& b) {
  const auto wa = weightsOf(a), wb = weightsOf(b);
  ASSERT_EQ(wa.size(), wb.size());
  for (std::size_t i = 0; i < wa.size(); ++i) {
    EXPECT_EQ(wa[i].name, wb[i].name);
    EXPECT_EQ(wa[i].values, wb[i].values) << wa[i].name << " differs";
  }
}

// Compares the loss.csv of two runs row by row: the seconds column differs between runs, the step and every
// loss must not. Returns the rows compared.
int expectSameLosses(const fs::path& a, const fs::path& b) {
  std::ifstream fa(a / "loss.csv"), fb(b / "loss.csv");
  std::string la, lb;
  int rows = 0;
  while (std::getline(fa, la) && std::getline(fb, lb)) {
    EXPECT_EQ(la.substr(0, la.find(',')), lb.substr(0, lb.find(',')));
    EXPECT_EQ(la.substr(la.find(',', la.find(',') + 1)), lb.substr(lb.find(',', lb.find(',') + 1))) << "row " << rows;
    ++rows;
  }
  return rows;
}

class TrainingTest : public GpuTest {};

// Training `config` (into a scratch run `run`, with the tiny models) is refused with an Error holding `fragment`.
void expectRefused(const networks::NetworkConfig& config, const std::string& run, const std::string& fragment,
                   const std::string& what) {
  try {
    trainTiny(config, scratch(run) / networks::networkName(config.network), -1, false, tinyModels());
    FAIL() << what << " was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST_F(TrainingTest, EveryNetworkTrainsAndWritesItsFiles) {
  const fs::path& models = tinyModels();
  for (const auto n : networks::allNetworks()) {
    const fs::path out = models / networks::networkName(n);
    for (const char* file : {"model.safetensors", "config.json", "model_card.md", "loss.csv", "loss.png", "validation.csv"})
      EXPECT_TRUE(fs::exists(out / file)) << networks::networkName(n) << ": " << file;
    EXPECT_FALSE(fs::exists(out / "checkpoint.safetensors")) << networks::networkName(n);
    // The weights load back into the architecture their config describes.
    const networks::NetworkConfig config = networks::readNetworkConfig(out / "config.json");
    EXPECT_EQ(config.network, n);
  }
}

TEST_F(TrainingTest, AKilledAndResumedRunEndsWithTheWeightsOfAnUninterruptedOne) {
  const fs::path& models = tinyModels();
  for (const auto n : {networks::Network::GrhoCoarse, networks::Network::SvDiff}) {
    const fs::path whole = scratch(networks::networkName(n) + "_whole"), pieces = scratch(networks::networkName(n) + "_pieces");
    trainTiny(n, whole, 8, -1, false, models);
    const train::TrainingResult first = trainTiny(n, pieces, 8, 4, false, models);  // "killed" after 4 steps
    EXPECT_FALSE(first.complete);
    EXPECT_TRUE(fs::exists(pieces / "checkpoint.safetensors"));
    const train::TrainingResult second = trainTiny(n, pieces, 8, -1, true, models);
    EXPECT_TRUE(second.complete);
    EXPECT_EQ(second.stepsThisCall, 5);  // resumed from the checkpoint at step 3
    expectSameWeights(whole, pieces);
    EXPECT_EQ(expectSameLosses(whole, pieces), 9);
  }
}

// Asked to stop (Ctrl-C: TrainingOptions::stop), a run goes on to its next log step, checkpoints there
// (between the regular checkpoints) and returns; resumed, it ends as an uninterrupted run does.
TEST_F(TrainingTest, ARunAskedToStopCheckpointsAtItsNextLogStepAndResumesBitForBit) {
  const fs::path& models = tinyModels();
  networks::NetworkConfig config = tinyConfig(networks::Network::GrhoCoarse, 8);
  config.train.logEvery = 3;
  config.train.checkpointEvery = 6;
  const fs::path whole = scratch("stop_whole"), pieces = scratch("stop_pieces");
  trainTiny(config, whole, -1, false, models);

  const dataset::SceneDataset data = tinySplit();
  const auto trainer = train::makeTrainer(testContext(), config, data, models);
  const std::atomic<bool> stop{true};  // asked before the first step: the run still reaches its first log step
  train::TrainingOptions o;
  o.out = pieces;
  o.quiet = true;
  o.seed = 7;
  o.stop = &stop;
  const train::TrainingResult stopped = train::runTraining(testContext(), *trainer, config, o);
  EXPECT_TRUE(stopped.stopped);
  EXPECT_FALSE(stopped.complete);
  EXPECT_EQ(stopped.steps, 3);
  EXPECT_TRUE(fs::exists(pieces / "checkpoint.safetensors"));
  EXPECT_FALSE(fs::exists(pieces / "model.safetensors"));

  const train::TrainingResult resumed = trainTiny(config, pieces, -1, true, models);
  EXPECT_TRUE(resumed.complete);
  EXPECT_FALSE(resumed.stopped);
  EXPECT_EQ(resumed.stepsThisCall, 5);  // from the stop's checkpoint at step 3, not the regular one's at 6
  expectSameWeights(whole, pieces);
  EXPECT_EQ(expectSameLosses(whole, pieces), 4);  // the header and steps 3, 6, 8
}

TEST_F(TrainingTest, TheSameSeedGivesTheSameWeights) {
  const fs::path a = scratch("seed_a"), b = scratch("seed_b");
  trainTiny(networks::Network::GrhoFine, a / "grho-fine", 5);
  trainTiny(networks::Network::GrhoFine, b / "grho-fine", 5);
  expectSameWeights(a / "grho-fine", b / "grho-fine");
}

TEST_F(TrainingTest, ARunFolderIsNeitherResumedNorOverwrittenUnasked) {
  const fs::path out = scratch("guarded") / "grho-fine";
  trainTiny(networks::Network::GrhoFine, out, 3);
  EXPECT_THROW(trainTiny(networks::Network::GrhoFine, out, 3), Error);
  // A finished run resumed is a no-op; a run of another config refuses to resume.
  EXPECT_EQ(trainTiny(networks::Network::GrhoFine, out, 3, -1, true).stepsThisCall, 0);
  EXPECT_THROW(trainTiny(networks::Network::GrhoFine, out, 4, -1, true), Error);
}

// NvRef with the mirrored front view in the side slot of every sample, and its history made as inference
// makes it (the coarse renders, or NvRef's own refinements of the previous frames): it trains, and
// validation reports the refinement with the true and with the mirrored side view.
TEST_F(TrainingTest, NvRefTrainsOnTheMirroredSideViewAndItsOwnHistory) {
  for (const char* history : {"coarse", "self"}) {
    networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
    config.options["mirrored_side"] = 1.0;
    config.options["history"] = history;
    if (std::string(history) == "self") {
      config.options["psnr_reference"] = "black";
      config.options["earlier_views"] = "coarse";
    }
    const fs::path out = scratch(std::string("nvref_") + history) / "nvref";
    EXPECT_TRUE(trainTiny(config, out, -1, false, tinyModels()).complete) << history;
    std::ifstream losses(out / "loss.csv");
    const std::string lossText((std::istreambuf_iterator<char>(losses)), std::istreambuf_iterator<char>());
    EXPECT_NE(lossText.find("psnr_gap"), std::string::npos) << lossText;
    EXPECT_EQ(lossText.find("nan"), std::string::npos) << history << ": " << lossText;
    std::ifstream csv(out / "validation.csv");
    std::string header, row;
    ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row)) << history;
    EXPECT_NE(header.find("psnr_gain,"), std::string::npos) << header;
    EXPECT_NE(header.find("psnr_refined_near_mirrored"), std::string::npos) << header;
    EXPECT_EQ(row.find("nan"), std::string::npos) << history << ": " << row;
    std::ifstream card(out / "model_card.md");
    const std::string cardText((std::istreambuf_iterator<char>(card)), std::istreambuf_iterator<char>());
    EXPECT_EQ(cardText.find("the mid and far stages' from the renders of the stage before") != std::string::npos,
              std::string(history) == "self")
        << cardText;
  }
  networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
  config.options["mirrored_side"] = 1.5;
  EXPECT_THROW(trainTiny(config, scratch("nvref_bad") / "nvref", -1, false, tinyModels()), Error);
  config.options["mirrored_side"] = 0.5;
  config.options["history"] = "oracle";
  expectRefused(config, "nvref_bad_history", "'history' must be \"truth\", \"coarse\" or \"self\", not \"oracle\"",
                "an unknown history");
  config.options["history"] = "self";
  config.options["psnr_reference"] = "truth";
  expectRefused(config, "nvref_bad_reference", "'psnr_reference' must be \"render\" or \"black\", not \"truth\"",
                "an unknown PSNR reference");
  config.options["psnr_reference"] = "black";
  config.options["earlier_views"] = "refined";
  expectRefused(config, "nvref_bad_earlier_views", "'earlier_views' must be \"truth\" or \"coarse\", not \"refined\"",
                "unknown earlier views");
}

// With earlier_views "coarse" the mid and far stages reconstruct their densities from the renders of the
// stage before instead of the true views; the near stage, which has no earlier views, is the same.
TEST_F(TrainingTest, NvRefsCoarseEarlierViewsChangeOnlyTheLaterStages) {
  const dataset::SceneDataset data = tinySplit();
  auto validation = [&](const char* earlier) {
    networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
    config.options["earlier_views"] = earlier;
    std::map<std::string, double> metrics;
    for (const train::Metric& m : train::makeTrainer(testContext(), config, data, tinyModels())->validate()) metrics[m.name] = m.value;
    return metrics;
  };
  const auto truth = validation("truth"), coarse = validation("coarse");
  for (const char* kind : {"unrefined", "refined"}) {
    const std::string name = std::string("psnr_") + kind + "_";
    EXPECT_EQ(truth.at(name + "near"), coarse.at(name + "near")) << kind;
    EXPECT_EQ(truth.at(name + "near_mirrored"), coarse.at(name + "near_mirrored")) << kind;
    for (const char* stage : {"mid", "far"}) EXPECT_NE(truth.at(name + stage), coarse.at(name + stage)) << kind << " " << stage;
  }
}

// options.stages restricts the stages training draws (with earlier_views "coarse" the stage is part of the
// drawn variant: variant / 6); validation still measures all three; bad lists are refused.
TEST_F(TrainingTest, NvRefTrainsOnTheStagesItIsGiven) {
  const dataset::SceneDataset data = tinySplit();
  for (const auto& [stages, expected] : std::vector<std::pair<std::vector<std::string>, std::set<int>>>{
           {{"far"}, {2}}, {{"mid", "near"}, {0, 1}}, {{"near", "mid", "far"}, {0, 1, 2}}}) {
    networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
    config.options["earlier_views"] = "coarse";
    config.options["stages"] = stages;
    const auto trainer = train::makeTrainer(testContext(), config, data, tinyModels());
    diffusion::Gaussian random(5);
    std::set<int> drawn;
    for (int step = 0; step < 24; ++step) drawn.insert(trainer->prepare(step, random) / 6);
    EXPECT_EQ(drawn, expected) << nlohmann::json(stages).dump();
    EXPECT_EQ(trainer->dataSummary().find("stage only") != std::string::npos, stages.size() == 1) << trainer->dataSummary();
  }
  networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
  config.options["stages"] = {"near", "middle"};
  expectRefused(config, "nvref_bad_stage", "'stages' holds \"middle\"; expected \"near\", \"mid\" or \"far\"", "an unknown stage");
  config.options["stages"] = {"far", "far"};
  expectRefused(config, "nvref_twice_stage", "'stages' names \"far\" twice", "a stage named twice");
  config.options["stages"] = nlohmann::json::array();
  expectRefused(config, "nvref_no_stage", "'stages' must be a non-empty list", "no stage");
}

// A folder of side views of every tiny scene's frames 0 .. frames-1, as `smokesvd rollout --keep-side-views` keeps
// them; here uniform noise in [0, 0.5): the trainer does not care where they come from.
fs::path tinySideViews(const std::string& name, int frames, int height = preset("tiny").imageHeight) {
  const fs::path folder = scratch(name);
  dataset::SideViewRolloutManifest m;
  m.preset = "tiny";
  m.frames = frames;
  m.height = height;
  m.width = preset("tiny").imageWidth;
  m.how = {{"history", "own"}, {"sampling", {{"seed", 0}}}};
  dataset::prepareSideViewFolder(folder, m);
  const dataset::SceneDataset data = tinySplit();
  diffusion::Gaussian random(17);
  for (const auto* split : {&data.training(), &data.validation()})
    for (const dataset::SceneEntry& scene : *split) {
      std::vector<float> sides(static_cast<std::size_t>(frames * m.height * m.width));
      for (float& v : sides) v = static_cast<float>(0.5 * random.uniform());
      dataset::writeSceneSideViews(folder, m, scene, sides);
    }
  return folder;
}

// NvRef with SvDiff's side views (options.side_views, options.synthesised_side) in the side slot of every
// sample, on its own history: it trains, the model card names the side views, and validation reports the
// refinement with them beside the true and the mirrored side view.
TEST_F(TrainingTest, NvRefTrainsOnSynthesisedSideViews) {
  networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
  config.options["side_views"] = tinySideViews("nvref_side_views", 6).string();
  config.options["synthesised_side"] = 1.0;
  config.options["history"] = "self";
  const fs::path out = scratch("nvref_synthesised") / "nvref";
  EXPECT_TRUE(trainTiny(config, out, -1, false, tinyModels()).complete);
  std::ifstream losses(out / "loss.csv");
  const std::string lossText((std::istreambuf_iterator<char>(losses)), std::istreambuf_iterator<char>());
  EXPECT_EQ(lossText.find("nan"), std::string::npos) << lossText;
  std::ifstream csv(out / "validation.csv");
  std::string header, row;
  ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row));
  for (const char* column : {"psnr_gain,", "psnr_gain_mirrored,", "psnr_gain_synthesised,", "psnr_refined_far_synthesised"})
    EXPECT_NE(header.find(column), std::string::npos) << header;
  EXPECT_EQ(row.find("nan"), std::string::npos) << row;
  std::ifstream card(out / "model_card.md");
  const std::string cardText((std::istreambuf_iterator<char>(card)), std::istreambuf_iterator<char>());
  EXPECT_NE(cardText.find("SvDiff's side views of 3 training and 1 held-out scenes, frames 0-5"), std::string::npos) << cardText;
}

TEST_F(TrainingTest, NvRefsSideViewOptionsAreChecked) {
  networks::NetworkConfig config = tinyConfig(networks::Network::NvRef, 3);
  config.options["synthesised_side"] = 0.5;
  expectRefused(config, "nvref_no_side_views", "'synthesised_side' needs 'side_views'", "synthesised sides without a folder");
  config.options["side_views"] = scratch("nvref_empty_side_views").string();
  expectRefused(config, "nvref_empty", "rollout.json: missing; make the side views with `smokesvd rollout --split training",
                "a folder without a rollout");
  config.options["side_views"] = tinySideViews("nvref_tall_side_views", 4, preset("tiny").imageHeight + 1).string();
  expectRefused(config, "nvref_tall", "expected the tiny preset's", "side views of another size");
  config.options["side_views"] = tinySideViews("nvref_good_side_views", 4).string();
  config.options["mirrored_side"] = 0.6;
  expectRefused(config, "nvref_shares", "'synthesised_side' must be a probability in [0, 1 - mirrored_side]",
                "shares of the side views above 1");
}

// A training step is recorded once per variant and resubmitted on every later sample of that variant, so
// whatever decides the recorded kernels (the look, the side view, the kind of input views) must be part
// of the variant: the resubmitted recording must give the loss that a fresh recording of the same sample
// gives. Checked on trainers whose samples mix kinds.
void expectRecordingsFollowTheirSamples(const networks::NetworkConfig& config, int kinds) {
  const dataset::SceneDataset data = tinySplit();
  const auto trainer = train::makeTrainer(testContext(), config, data, tinyModels());
  struct Recorded {
    explicit Recorded(Context& context) : stream(context), tape(stream) {}
    Stream stream;
    Tape tape;
    train::LossTerms terms;
  };
  std::map<int, std::unique_ptr<Recorded>> recordings;
  int resubmitted = 0;
  for (int64_t step = 0; step < 24; ++step) {
    diffusion::Gaussian random = train::stepRandom(3, step);
    const int variant = trainer->prepare(step, random);
    ASSERT_LT(variant, static_cast<int>(trainer->variants().size()));
    auto& recorded = recordings[variant];
    if (!recorded) {
      recorded = std::make_unique<Recorded>(testContext());
      recorded->terms = trainer->record(recorded->tape, variant);
      continue;
    }
    recorded->stream.submit();
    const float again = recorded->terms.total->value.download()[0];
    Recorded fresh(testContext());
    fresh.terms = trainer->record(fresh.tape, variant);
    fresh.stream.submit();
    const float expected = fresh.terms.total->value.download()[0];
    EXPECT_NEAR(again, expected, 1e-4 * std::abs(expected) + 1e-7)
        << networks::networkName(config.network) << " step " << step << ", variant " << trainer->variants()[static_cast<std::size_t>(variant)];
    ++resubmitted;
  }
  EXPECT_GE(static_cast<int>(recordings.size()), kinds) << "the samples did not mix the kinds";
  EXPECT_GT(resubmitted, 0);
}

TEST_F(TrainingTest, ARecordedStepResubmittedOnAnotherSampleGivesThatSamplesLoss) {
  networks::NetworkConfig nvref = tinyConfig(networks::Network::NvRef, 3);
  nvref.options["mirrored_side"] = 0.5;
  expectRecordingsFollowTheirSamples(nvref, 2);
  nvref.options["mirrored_side"] = 0.3;
  nvref.options["synthesised_side"] = 0.4;
  nvref.options["side_views"] = tinySideViews("recorded_side_views", 8).string();
  expectRecordingsFollowTheirSamples(nvref, 3);
  nvref.options["earlier_views"] = "coarse";
  expectRecordingsFollowTheirSamples(nvref, 5);
  networks::NetworkConfig fine = tinyConfig(networks::Network::GrhoFine, 3);
  fine.options["inference_views"] = 0.7;
  fine.options["mirrored_side"] = 0.5;
  fine.options["coarse_model"] = "grho-coarse";
  expectRecordingsFollowTheirSamples(fine, 3);
}

// SvDiff with options.multi_frame_steps "all" chains its frames on unguided steps too: on the same sample, its
// unguided noise term averages the F frames (the first of which is the paper's one frame, the others
// conditioned on the estimates before them), so it differs from the paper's; the guidance terms stay zero.
TEST_F(TrainingTest, SvDiffChainsItsFramesOnUnguidedStepsWhenAsked) {
  const dataset::SceneDataset data = tinySplit();
  auto unguidedTerms = [&](const std::string& steps) {
    networks::NetworkConfig config = tinyConfig(networks::Network::SvDiff, 3);
    config.options["multi_frame_steps"] = steps;
    const auto trainer = train::makeTrainer(testContext(), config, data, tinyModels());
    for (int64_t step = 0;; ++step) {
      diffusion::Gaussian random = train::stepRandom(5, step);
      const int variant = trainer->prepare(step, random);
      if (trainer->variants()[static_cast<std::size_t>(variant)].rfind("unguided", 0) != 0) continue;
      Stream stream(testContext());
      Tape tape(stream);
      const train::LossTerms terms = trainer->record(tape, variant);
      stream.submit();
      std::map<std::string, float> values;
      for (const auto& [name, term] : terms.terms) values[name] = term->value.download()[0];
      return values;
    }
  };
  const auto paper = unguidedTerms("guided"), chained = unguidedTerms("all");
  EXPECT_GT(chained.at("noise"), 0.0f);
  EXPECT_NE(chained.at("noise"), paper.at("noise"));
  for (const char* guidance : {"image", "row_sum", "velocity"}) {
    EXPECT_EQ(paper.at(guidance), 0.0f) << guidance;
    EXPECT_EQ(chained.at(guidance), 0.0f) << guidance;
  }
  networks::NetworkConfig bad = tinyConfig(networks::Network::SvDiff, 2);
  bad.options["multi_frame_steps"] = "some";
  expectRefused(bad, "svdiff_bad_multi_frame_steps", "'multi_frame_steps' must be \"guided\" or \"all\", not \"some\"",
                "multi_frame_steps \"some\"");
}

// SvDiff with options.init_history: a sample drawn so is conditioned on SvDiff-init's estimates of its two
// previous side views instead of the truth. On the same sample the noise term changes (the history did), the
// variant says so, and a bad probability or a missing model is refused.
TEST_F(TrainingTest, SvDiffTrainsOnSvDiffInitsHistoryWhenAsked) {
  const dataset::SceneDataset data = tinySplit();
  auto firstUnguided = [&](double initHistory) {
    networks::NetworkConfig config = tinyConfig(networks::Network::SvDiff, 3);
    if (initHistory > 0) {
      config.options["init_history"] = initHistory;
      config.options["init_model"] = "svdiff-init";
    }
    const auto trainer = train::makeTrainer(testContext(), config, data, tinyModels());
    // A fresh SvDiff's output layer is zero (its initialisation), so its output would not depend on the
    // condition: set to 0.05 everywhere, so that the loss shows what the condition holds.
    for (const auto& [parameter, value] : trainer->model().namedParameters())
      if (parameter == "conv_out.weight") value->value.upload(std::vector<float>(static_cast<std::size_t>(value->value.numel()), 0.05f));
    for (int64_t step = 0;; ++step) {
      diffusion::Gaussian random = train::stepRandom(5, step);
      const int variant = trainer->prepare(step, random);
      const std::string name = trainer->variants()[static_cast<std::size_t>(variant)];
      if (name.rfind("unguided", 0) != 0) continue;
      Stream stream(testContext());
      Tape tape(stream);
      const train::LossTerms terms = trainer->record(tape, variant);
      stream.submit();
      return std::make_pair(name, terms.terms.at(0).second->value.download()[0]);
    }
  };
  const auto truth = firstUnguided(0), estimated = firstUnguided(1);
  EXPECT_EQ(truth.first.find("init-history"), std::string::npos) << truth.first;
  EXPECT_EQ(estimated.first, truth.first + "-init-history");
  EXPECT_GT(estimated.second, 0.0f);
  EXPECT_NE(estimated.second, truth.second);

  networks::NetworkConfig bad = tinyConfig(networks::Network::SvDiff, 2);
  bad.options["init_history"] = 1.5;
  bad.options["init_model"] = "svdiff-init";
  expectRefused(bad, "svdiff_bad_init_history", "'init_history' must be a probability in [0, 1]", "init_history 1.5");
  bad.options["init_history"] = 0.5;
  bad.options.erase("init_model");
  expectRefused(bad, "svdiff_no_init_model", "'init_model'", "init_history without init_model");
}

// The fine G_rho trained on the views the reconstruction gives it (the coarse G_rho's renders at the 14
// other slots): it trains, and validation says what it gains over the coarse density it was given.
TEST_F(TrainingTest, FineDensityTrainsOnInferenceLikeViews) {
  networks::NetworkConfig config = tinyConfig(networks::Network::GrhoFine, 3);
  config.options["inference_views"] = 0.5;
  config.options["mirrored_side"] = 0.5;
  config.options["coarse_model"] = "grho-coarse";
  const fs::path out = scratch("grho_inference_views") / "grho-fine";
  EXPECT_TRUE(trainTiny(config, out, -1, false, tinyModels()).complete);
  std::ifstream csv(out / "validation.csv");
  std::string header, row;
  ASSERT_TRUE(std::getline(csv, header) && std::getline(csv, row));
  for (const char* column : {"psnr_all_views,", "psnr_novel_inference,", "psnr_novel_coarse,", "psnr_gain_inference,",
                             "psnr_novel_inference_mirrored,", "psnr_gain_inference_mirrored"})
    EXPECT_NE(header.find(column), std::string::npos) << column << " in " << header;
  EXPECT_EQ(row.find("nan"), std::string::npos) << row;
  networks::NetworkConfig coarse = tinyConfig(networks::Network::GrhoCoarse, 3);
  coarse.options["inference_views"] = 0.5;
  coarse.options["coarse_model"] = "grho-coarse";
  expectRefused(coarse, "grho_inference_views_coarse", "belong to the fine G_rho", "inference-like views for the coarse G_rho");
  networks::NetworkConfig sideAlone = tinyConfig(networks::Network::GrhoFine, 3);
  sideAlone.options["mirrored_side"] = 0.5;
  expectRefused(sideAlone, "grho_mirrored_side_alone", "needs 'inference_views'", "mirrored_side without inference_views");
  config.options.erase("coarse_model");
  expectRefused(config, "grho_inference_views_no_coarse", "'coarse_model': \"grho-coarse\"",
                "inference-like views without a coarse model");
}

TEST(TrainingInputs, BadDataAndConfigsAreClearErrors) {
  const fs::path empty = scratch("empty");
  try {
    dataset::SceneDataset data(empty, preset("tiny"));
    FAIL() << "an empty folder was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no scenes"), std::string::npos) << e.what();
  }
  try {
    dataset::SceneDataset data(tinyData(), preset("small"));
    FAIL() << "scenes of another resolution were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("resolution 16x28x16"), std::string::npos) << e.what();
  }
  try {
    networks::parseNetwork("grho");
    FAIL() << "'grho' was taken for one network";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("grho-coarse (the front and side views"), std::string::npos) << e.what();
  }
  EXPECT_THROW(networks::parseNetwork("gx"), Error);
  try {
    networks::readNetworkConfig(tinyModels() / "gu" / "config.json", networks::Network::NvRef);
    FAIL() << "G_u's config was read as NvRef's";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gu/config.json: configures gu, not nvref"), std::string::npos) << e.what();
  }
  EXPECT_EQ(networks::readNetworkConfig(tinyModels() / "gu" / "config.json", networks::Network::Gu).network,
            networks::Network::Gu);
  nlohmann::json config = networks::toJson(networks::defaultNetworkConfig("tiny", networks::Network::Gu));
  config["train"]["learning_rate"] = 1e-3;
  try {
    networks::parseNetworkConfig(config, "mine.json");
    FAIL() << "an unknown key was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mine.json [train]: unknown key 'learning_rate'"), std::string::npos) << e.what();
  }
  config = networks::toJson(networks::defaultNetworkConfig("tiny", networks::Network::Gu));
  config["model"]["filters"] = "many";
  EXPECT_THROW(
      {
        const networks::NetworkConfig c = networks::parseNetworkConfig(config, "mine.json");
        dataset::DatasetOptions o;
        o.validationEvery = 4;
        const dataset::SceneDataset data(tinyData(), preset("tiny"), o);
        train::makeTrainer(testContext(), c, data, {});
      },
      Error);
}

// The EMA of a run started from --init weights starts from those weights, not from the random ones they
// replace: with a learning rate too small to move anything, the run ends with the weights it began with.
TEST_F(TrainingTest, ARunFromInitialWeightsAveragesFromThem) {
  const fs::path& models = tinyModels();
  networks::NetworkConfig config = tinyConfig(networks::Network::GrhoFine, 4);
  config.train.lr = 1e-12;
  config.train.warmup = 0;
  const dataset::SceneDataset data = tinySplit();
  const auto trainer = train::makeTrainer(testContext(), config, data, models);
  train::TrainingOptions o;
  o.out = scratch("from_init") / "grho-fine";
  o.quiet = true;
  o.initWeights = models / "grho-fine" / "model.safetensors";
  ASSERT_TRUE(train::runTraining(testContext(), *trainer, config, o).complete);
  const auto start = weightsOf(models / "grho-fine"), end = weightsOf(o.out);
  ASSERT_EQ(start.size(), end.size());
  for (std::size_t i = 0; i < start.size(); ++i) {
    ASSERT_EQ(start[i].values.size(), end[i].values.size()) << start[i].name;
    for (std::size_t k = 0; k < start[i].values.size(); ++k)
      ASSERT_NEAR(end[i].values[k], start[i].values[k], 1e-6f + 1e-5f * std::abs(start[i].values[k])) << start[i].name << "[" << k << "]";
  }
}

TEST_F(TrainingTest, WeightsOfAnotherArchitectureNameEveryDifference) {
  const fs::path& models = tinyModels();
  // A G_u checkpoint given as the initial weights of G_rho: the error lists the tensors that differ.
  try {
    const fs::path out = scratch("other_architecture");
    const networks::NetworkConfig config = tinyConfig(networks::Network::GrhoFine, 2);
    const dataset::SceneDataset data = tinySplit();
    const auto trainer = train::makeTrainer(testContext(), config, data, models);
    train::TrainingOptions o;
    o.out = out;
    o.quiet = true;
    o.initWeights = models / "gu" / "model.safetensors";
    train::runTraining(testContext(), *trainer, config, o);
    FAIL() << "weights of another architecture were accepted";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("holds a gu model of the tiny preset, and the config is of grho-fine at the tiny preset; "),
              std::string::npos) << what;
    EXPECT_NE(what.find("does not match"), std::string::npos) << what;
    EXPECT_NE(what.find("presence.weight"), std::string::npos) << what;
    EXPECT_NE(what.find("with a different shape: stem.weight"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace smokesvd::testing
