// Validating a trained model without training (train::validateModel, `smokesvd validate`): each tiny model's
// validation from its model.safetensors and config.json gives the metrics its run's last validation wrote,
// and weights of another network are an error that says whose they are.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/preset.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/train/training_run.h"
#include "pipeline/train/validate_model.h"
#include "runtime/error.h"
#include "tests/harness/command.h"
#include "tests/harness/gpu_test.h"
#include "tests/pipeline/tiny_models.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
  return cells;
}

// The header and the last row of a run's validation.csv.
std::pair<std::vector<std::string>, std::vector<std::string>> lastValidation(const fs::path& run) {
  std::ifstream in(run / "validation.csv");
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return {splitCsv(header), splitCsv(last)};
}

// Expects `metrics` to be the last row of `run`'s validation.csv, every column's name and value (written to 9
// significant digits); the row's step, where `step` is given, to be it.
void expectLastValidation(const fs::path& run, const std::vector<train::Metric>& metrics, const std::string& step = "") {
  const auto [columns, values] = lastValidation(run);
  ASSERT_EQ(columns.size(), metrics.size() + 1) << run;  // the step, then the metrics
  if (!step.empty()) {
    EXPECT_EQ(values.at(0), step) << run;
  }
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    EXPECT_EQ(metrics[i].name, columns[i + 1]) << run;
    const double written = std::stod(values.at(i + 1));
    EXPECT_NEAR(metrics[i].value, written, 1e-8 * std::abs(written) + 1e-12) << run << ": " << metrics[i].name;
  }
}

dataset::SceneDataset tinyData(const networks::NetworkConfig& config) {
  dataset::DatasetOptions options;
  options.validationEvery = config.data.validationEvery;
  return dataset::SceneDataset(tinyDataset(), preset("tiny"), options);
}

class ValidateModelTest : public GpuTest {};

TEST_F(ValidateModelTest, EachModelScoresWhatItsRunsLastValidationWrote) {
  for (const networks::Network n : networks::allNetworks()) {
    const std::string name = networks::networkName(n);
    const fs::path run = tinyModels() / name;
    const networks::NetworkConfig config = networks::readNetworkConfig(run / "config.json");
    const std::vector<train::Metric> metrics =
        train::validateModel(testContext(), config, tinyData(config), tinyModels(), run / "model.safetensors");
    expectLastValidation(run, metrics);
  }
}

// A run's checkpoint stands for the model it would write at that step: its EMA weights, the ones the run's
// validation at that step measured.
TEST_F(ValidateModelTest, ACheckpointScoresWhatItsRunsValidationAtThatStepWrote) {
  networks::NetworkConfig config = networks::readNetworkConfig(tinyModels() / "grho-coarse" / "config.json");
  config.train.steps = 6;
  config.train.checkpointEvery = 3;
  config.train.validateEvery = 3;
  const dataset::SceneDataset data = tinyData(config);
  const auto trainer = train::makeTrainer(testContext(), config, data, tinyModels());
  train::TrainingOptions o;
  o.out = tinyScratch("validate_checkpoint") / "grho-coarse";
  o.quiet = true;
  o.seed = 3;
  o.stopAfter = 4;  // "killed" after step 4: the checkpoint of step 3 stays
  ASSERT_FALSE(train::runTraining(testContext(), *trainer, config, o).complete);
  const std::vector<train::Metric> metrics =
      train::validateModel(testContext(), config, data, tinyModels(), o.out / "checkpoint.safetensors");
  expectLastValidation(o.out, metrics, "3");
}

TEST_F(ValidateModelTest, WeightsOfAnotherNetworkSayWhoseTheyAre) {
  const networks::NetworkConfig config = networks::readNetworkConfig(tinyModels() / "gu" / "config.json");
  try {
    train::validateModel(testContext(), config, tinyData(config), tinyModels(),
                         tinyModels() / "nvref" / "model.safetensors");
    FAIL() << "NvRef's weights were validated as G_u's";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("holds a nvref model of the tiny preset, and the config is of gu"),
              std::string::npos) << e.what();
  }
}

// `smokesvd validate` as a user runs it: the metrics on stdout and in --json, the config beside the weights
// by default, and one-line errors for what does not fit.
TEST_F(ValidateModelTest, TheCommandPrintsTheMetricsAndWritesThemAsJson) {
  const fs::path json = tinyScratch("validate_command") / "gu.json";
  const std::string where = " --data " + tinyDataset().string() + " --models " + tinyModels().string();
  const CommandResult r = runSmokesvd("validate gu" + where + " --json " + json.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("advection_error_ratio "), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("on the 1 held-out scenes"), std::string::npos) << r.err;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(json));
  EXPECT_EQ(report.at("network"), "gu");
  EXPECT_EQ(report.at("preset"), "tiny");
  // The JSON's metrics in the order of validation.csv's columns (a JSON object keeps its keys sorted).
  const auto [columns, values] = lastValidation(tinyModels() / "gu");
  std::vector<train::Metric> metrics;
  for (std::size_t i = 1; i < columns.size(); ++i)
    if (report.at("metrics").contains(columns[i])) metrics.push_back({columns[i], report.at("metrics").at(columns[i]).get<double>()});
  EXPECT_EQ(metrics.size(), report.at("metrics").size());
  expectLastValidation(tinyModels() / "gu", metrics);

  const CommandResult missing = runSmokesvd("validate gu" + where + " --weights " + (tinyModels() / "nope.safetensors").string());
  EXPECT_EQ(missing.exitCode, 1);
  EXPECT_NE(missing.err.find("nope.safetensors: no such weights"), std::string::npos) << missing.err;
  const CommandResult other =
      runSmokesvd("validate gu" + where + " --config " + (tinyModels() / "nvref" / "config.json").string());
  EXPECT_EQ(other.exitCode, 1);
  EXPECT_NE(other.err.find("configures nvref, not gu"), std::string::npos) << other.err;
  const CommandResult both = runSmokesvd("validate gu" + where + " --preset tiny --config " +
                                         (tinyModels() / "gu" / "config.json").string());
  EXPECT_EQ(both.exitCode, 2);
  EXPECT_NE(both.err.find("--config excludes --preset"), std::string::npos) << both.err;
}

}  // namespace
}  // namespace smokesvd::testing
