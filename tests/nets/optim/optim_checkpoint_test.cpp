#include <gtest/gtest.h>


#include <filesystem>

#include "nets/io/safetensors.h"
#include "nets/io/temporary_folder.h"
#include "nets/optim/checkpoint.h"
#include "runtime/error.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::testing {
namespace {

namespace fs = std::filesystem;
using namespace optim;

// A toy model (three parameters, initialised from `seed`; the optimiser keeps the two small ones' state in
// flat tensors and the large one's apart) trained on fixed gradients, with Adam and an EMA.
struct Trainer {
  NamedParameters parameters;
  std::unique_ptr<Adam> adam;
  std::unique_ptr<Ema> ema;

  Trainer(Context& context, AdamOptions options, uint64_t seed) {
    uint64_t gradientSeed = 100;
    for (const auto& [name, shape] : {std::pair<std::string, Shape>{"layer.weight", {3, 5}}, {"layer.bias", {3}}, {"big.weight", {3, 44001}}}) {
      Var p = variable(randomTensor(context, shape, seed++), true);
      p->grad = randomTensor(context, shape, gradientSeed++);
      parameters.emplace_back(name, p);
    }
    adam = std::make_unique<Adam>(context, parameters, options);
    ema = std::make_unique<Ema>(context, parameters, 0.9);
  }
  void train(Context& context, int steps) const {
    Stream stream(context);
    adam->step(stream);
    ema->update(stream);
    for (int i = 0; i < steps; ++i) stream.submit();
  }
  std::vector<std::vector<float>> values() const {
    std::vector<std::vector<float>> all;
    for (const auto& [name, p] : parameters) all.push_back(p->value.download());
    for (const auto& [name, t] : ema->namedShadows()) all.push_back(t.download());
    return all;
  }
};

class CheckpointTest : public GpuTest {
 protected:
  io::TemporaryFolder directory_{"checkpoint"};
};

// Training 3 steps, saving, and training 4 more equals loading that checkpoint into a fresh model and
// training 4 steps: moments, step counter (bias corrections, schedule) and EMA all carry over.
TEST_F(CheckpointTest, ResumedTrainingEqualsUninterruptedTraining) {
  const AdamOptions options = AdamOptions::adamW(LrSchedule::cosine(1e-2, 10, 1e-3, 2), 0.1);
  const fs::path file = directory_ / "step3.safetensors";
  Trainer original(context(), options, 1);
  original.train(context(), 3);
  saveCheckpoint(file, original.parameters, *original.adam, original.ema.get(), {{"run", "test"}});
  original.train(context(), 4);

  Trainer resumed(context(), options, 50);
  const auto metadata = loadCheckpoint(file, resumed.parameters, *resumed.adam, resumed.ema.get());
  EXPECT_EQ(metadata.at("run"), "test");
  EXPECT_EQ(metadata.at("step"), "3");
  EXPECT_EQ(metadata.at("optimizer"), "adamw");
  EXPECT_EQ(resumed.adam->steps(), 3);
  resumed.train(context(), 4);
  EXPECT_EQ(resumed.values(), original.values());

  // The documented names.
  const io::SafetensorsFile contents = io::readSafetensors(file);
  std::vector<std::string> names;
  for (const auto& tensor : contents.tensors) names.push_back(tensor.name);
  EXPECT_EQ(names, (std::vector<std::string>{"layer.weight", "layer.bias", "big.weight",
                                             "optimizer.layer.weight.exp_avg", "optimizer.layer.weight.exp_avg_sq",
                                             "optimizer.layer.bias.exp_avg", "optimizer.layer.bias.exp_avg_sq",
                                             "optimizer.big.weight.exp_avg", "optimizer.big.weight.exp_avg_sq",
                                             "ema.layer.weight", "ema.layer.bias", "ema.big.weight"}));
  EXPECT_EQ(contents.metadata.at("format"), "smokesvd-checkpoint");
}

TEST_F(CheckpointTest, MismatchesAreRejectedAndNothingIsLoaded) {
  const fs::path file = directory_ / "c.safetensors";
  Trainer saved(context(), AdamOptions{}, 1);
  saved.train(context(), 2);
  saveCheckpoint(file, saved.parameters, *saved.adam, saved.ema.get());

  Trainer other(context(), AdamOptions{}, 9);
  const auto before = other.values();
  try {
    loadCheckpoint(file, other.parameters, *other.adam);  // no EMA to load into
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("3 unexpected: ema.layer.weight, ema.layer.bias, ema.big.weight"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(other.values(), before);
  EXPECT_EQ(other.adam->steps(), 0);

  Trainer adamW(context(), AdamOptions::adamW(LrSchedule::constant(1e-3)), 9);
  EXPECT_THROW(loadCheckpoint(file, adamW.parameters, *adamW.adam, adamW.ema.get()), Error);

  io::writeSafetensors(directory_ / "weights.safetensors", io::downloadNamed({{"layer.bias", Tensor(context(), {3})}}));
  try {
    loadCheckpoint(directory_ / "weights.safetensors", other.parameters, *other.adam);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a training checkpoint"), std::string::npos) << e.what();
  }
}

// A checkpoint's EMA weights under the model's own names, the metadata kept; a checkpoint without an EMA
// and a plain weights file are told apart.
TEST_F(CheckpointTest, TheEmaWeightsOfACheckpointComeUnderTheModelsNames) {
  Trainer trainer(context(), AdamOptions{}, 1);
  trainer.train(context(), 3);
  saveCheckpoint(directory_ / "ema.safetensors", trainer.parameters, *trainer.adam, trainer.ema.get(), {{"network", "x"}});
  const io::SafetensorsFile file = io::readSafetensors(directory_ / "ema.safetensors");
  ASSERT_TRUE(isCheckpoint(file));
  const io::SafetensorsFile weights = checkpointEmaWeights(file, "ema.safetensors");
  EXPECT_EQ(weights.metadata.at("network"), "x");
  const auto shadows = trainer.ema->namedShadows();
  ASSERT_EQ(weights.tensors.size(), shadows.size());
  for (const auto& [name, shadow] : shadows) {
    const io::NamedArray* tensor = weights.find(name);
    ASSERT_NE(tensor, nullptr) << name;
    EXPECT_EQ(tensor->shape, shadow.shape());
    EXPECT_EQ(tensor->values, shadow.download()) << name;
  }

  saveCheckpoint(directory_ / "plain.safetensors", trainer.parameters, *trainer.adam);
  try {
    checkpointEmaWeights(io::readSafetensors(directory_ / "plain.safetensors"), "plain.safetensors");
    FAIL() << "a checkpoint without an EMA gave EMA weights";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("plain.safetensors: the checkpoint holds no EMA weights"), std::string::npos) << e.what();
  }
  io::writeSafetensors(directory_ / "weights.safetensors", io::downloadNamed({{"layer.bias", Tensor(context(), {3})}}));
  EXPECT_FALSE(isCheckpoint(io::readSafetensors(directory_ / "weights.safetensors")));
}

}  // namespace
}  // namespace smokesvd::testing
