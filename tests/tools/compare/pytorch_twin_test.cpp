#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "nets/functional/broadcast.h"
#include "nets/io/npy.h"
#include "nets/io/temporary_folder.h"
#include "nets/models/model_json.h"
#include "nets/modules/weights.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/networks/refiner.h"
#include "pipeline/networks/side_view_synthesizer.h"
#include "pipeline/networks/velocity_generator.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/preset.h"
#include "tests/harness/gpu_test.h"
#include "tests/harness/random.h"

namespace smokesvd::networks {

// Test names and messages show the network by name.
void PrintTo(Network network, std::ostream* out) { *out << networkName(network); }

}  // namespace smokesvd::networks

namespace smokesvd::testing {
namespace {

// Every network of the tiny preset, built here with random values in every parameter, against its
// PyTorch twin (tools/compare/smokesvd_models.py) run on the same weights (model.safetensors), config
// (config.json) and random inputs: the architecture on its input x (with every deep-supervision head of
// the UNet3+ networks) and the network with its input encoding (pipeline/networks). The twin runs in
// float64, so the figures measure smokesvd's float32 arithmetic. Criterion, for every output array y
// against the twin's t (shapes equal, every element finite):
//   max_i |y_i - t_i| <= 1e-4 max_i |t_i|
// and the weights the twin writes back load here and equal the originals bit for bit.
// Skipped, with a message, when no Python 3 on this machine imports torch and numpy.

namespace fs = std::filesystem;
using networks::Network;

constexpr double kTolerance = 1e-4;

std::string slurp(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// /usr/bin/python3 first: the python3 on PATH may be another installation without Debian's torch.
const std::string& torchPython() {
  static const std::string found = [] {
    for (const std::string candidate : {"/usr/bin/python3", "python3"})
      if (std::system((candidate + " -c 'import torch, numpy' >/dev/null 2>&1").c_str()) == 0) return candidate;
    return std::string();
  }();
  return found;
}

// Every parameter uniform on [-b, b): b = sqrt(3 / fan_in) for weights (fan_in = values per output row),
// 0.5 for biases and norm scales, so that no rule of the networks' own initialisation (zero convs,
// GroupNorm's ones) hides a parameter from the comparison.
void randomizeEveryParameter(const modules::Module& module, uint64_t seed) {
  for (const auto& [name, p] : module.namedParameters()) {
    const Tensor& value = p->value;
    const double fanIn = static_cast<double>(value.numel()) / static_cast<double>(value.size(0));
    const double bound = value.rank() > 1 ? std::sqrt(3.0 / fanIn) : 0.5;
    value.upload(randomValues(static_cast<std::size_t>(value.numel()), seed++, static_cast<float>(-bound),
                              static_cast<float>(bound)));
  }
}

class PyTorchTwinTest : public GpuTest, public ::testing::WithParamInterface<Network> {
 protected:
  // A random input: uploaded for smokesvd and written for the twin under `key`.
  Var input(const std::string& key, const Shape& shape, float low, float high) {
    std::vector<float> values;
    const Var v = variable(randomTensor(context(), shape, seed_++, low, high, &values));
    write(key, shape, values);
    return v;
  }
  Var given(const std::string& key, const Shape& shape, const std::vector<float>& values) {
    write(key, shape, values);
    return variable(Tensor::fromHost(context(), shape, values));
  }
  // An input for the twin only.
  void write(const std::string& key, const Shape& shape, const std::vector<float>& values) {
    inputs_[key] = io::NpyArray::fromFloats(shape, values);
  }
  // A smokesvd output the twin must reproduce under `key`.
  void expect(const std::string& key, const Var& output) { expected_[key] = output; }
  // The UNet3+ outputs: y and every deep-supervision head.
  void expect(const models::UNet3PlusOutput& out) {
    expect("y", out.output);
    for (std::size_t k = 0; k < out.supervision.size(); ++k)
      expect("supervision_" + std::to_string(k + 1), out.supervision[k]);
  }

  // Writes config, weights and inputs, runs the twin and compares every expected output; the weights the
  // twin writes back (its state_dict) must load here strictly and equal the originals bit for bit.
  void compareWithTwin(modules::Module& net) {
    const io::TemporaryFolder folder("twin");
    {
      std::ofstream config(folder / "config.json");
      config << networks::toJson(config_).dump(2);
    }
    modules::saveWeights(folder / "model.safetensors", net);
    io::writeNpz(folder / "inputs.npz", inputs_);
    const std::string command = torchPython() + " " SMOKESVD_SOURCE_DIR "/tools/compare/smokesvd_models.py " +
                                folder.path().string() + " --inputs " + folder.file("inputs.npz") +
                                " --out " + folder.file("outputs.npz") + " --deep-supervision --dtype float64" +
                                " --save-weights " + folder.file("resaved.safetensors") +
                                " 2>" + folder.file("stderr.txt");
    const int status = std::system(command.c_str());
    ASSERT_TRUE(status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << command << "\n" << slurp(folder / "stderr.txt");
    const std::map<std::string, io::NpyArray> twin = io::readNpz(folder / "outputs.npz");
    ASSERT_EQ(twin.size(), expected_.size()) << "the twin's outputs differ from those expected";
    for (const auto& [key, output] : expected_) {
      const auto found = twin.find(key);
      ASSERT_NE(found, twin.end()) << "the twin wrote no '" << key << "'";
      compare(key, output->value.download(), output->value.shape(), found->second);
    }
    std::vector<std::vector<float>> original;
    for (const auto& [name, p] : net.namedParameters()) original.push_back(p->value.download());
    modules::loadWeights(folder / "resaved.safetensors", net);
    std::size_t i = 0;
    for (const auto& [name, p] : net.namedParameters()) EXPECT_EQ(p->value.download(), original[i++]) << name;
  }

  networks::NetworkConfig config_ = networks::defaultNetworkConfig("tiny", GetParam());
  const Preset& preset_ = preset("tiny");

 private:
  void compare(const std::string& key, const std::vector<float>& ours, const Shape& shape, const io::NpyArray& theirs) {
    ASSERT_EQ(theirs.shape, shape) << key;
    const std::vector<float> reference = theirs.toFloat();
    double difference = 0, scale = 0;
    for (std::size_t i = 0; i < ours.size(); ++i) {
      ASSERT_TRUE(std::isfinite(ours[i]) && std::isfinite(reference[i])) << key << " element " << i;
      difference = std::max(difference, std::abs(static_cast<double>(ours[i]) - reference[i]));
      scale = std::max(scale, std::abs(static_cast<double>(reference[i])));
    }
    ASSERT_GT(scale, 0.0) << key << " is zero: the comparison would say nothing";
    std::printf("  %-12s %-14s max|smokesvd - torch| / max|torch| = %.2e  (max|torch| = %.3g)\n",
                networks::networkName(GetParam()).c_str(), key.c_str(), difference / scale, scale);
    EXPECT_LE(difference, kTolerance * scale) << key;
  }

  uint64_t seed_ = 100;
  std::map<std::string, io::NpyArray> inputs_;
  std::map<std::string, Var> expected_;
};

TEST_P(PyTorchTwinTest, ReproducesTheNetwork) {
  if (torchPython().empty())
    GTEST_SKIP() << "no Python 3 that imports torch and numpy (/usr/bin/python3 or python3 on PATH); "
                    "tools/install-deps.sh installs Debian's python3-torch python3-numpy";
  const Network network = GetParam();
  const std::string where = config_.source + " [model]";
  const GridSize& grid = preset_.grid;
  const int64_t h = preset_.imageHeight, w = preset_.imageWidth;
  Stream stream(context());
  Tape tape(stream);
  NoGrad noGrad(tape);

  if (network == Network::GrhoCoarse || network == Network::GrhoFine) {
    networks::DensityGenerator generator(context(), models::unet3PlusFromJson(config_.model, where), preset_);
    randomizeEveryParameter(generator.net(), 1);
    // Views in four slots (front, side and two others), one presence for both calls.
    std::vector<float> slots(networks::kSlots, 0.0f);
    std::vector<std::pair<int, Var>> views;
    for (const int slot : {networks::kFrontSlot, 3, networks::kSideSlot, 13}) {
      slots[static_cast<std::size_t>(slot)] = 1;
      views.emplace_back(slot, variable(randomTensor(context(), {1, 1, h, w}, 10 + static_cast<uint64_t>(slot), 0, 1)));
    }
    const Var presence = given("presence", {networks::kSlots}, slots);
    // Architecture: a random volume.
    const Var x = input("x", {1, networks::kSlots, grid.z, grid.y, grid.x}, 0, 1);
    expect(generator.net().forward(tape, x, fn::reshape(tape, presence, {1, networks::kSlots}), true));
    // Network: the views lifted here; the twin gets the lifted volume.
    const Var images = generator.slotImages(tape, views);
    const Var lifted = diff::lift(tape, images, generator.views(), generator.grid());
    expect("density", generator.forward(tape, images, presence).density);
    stream.submit();
    write("lifted", {networks::kSlots, grid.z, grid.y, grid.x}, lifted->value.download());
    compareWithTwin(generator.net());
    return;
  }
  if (network == Network::Gu) {
    networks::VelocityGenerator generator(context(), models::unet3PlusFromJson(config_.model, where), preset_);
    randomizeEveryParameter(generator.net(), 2);
    expect(generator.net().forward(tape, input("x", {1, 2, grid.z, grid.y, grid.x}, 0, 1), nullptr, true));
    const Var current = input("current", grid.volume(), 0, 1), next = input("next", grid.volume(), 0, 1);
    expect("velocity", generator.forward(tape, current, next).velocity);
    stream.submit();
    compareWithTwin(generator.net());
    return;
  }
  if (network == Network::NvRef) {
    networks::Refiner refiner(context(), models::unet3PlusFromJson(config_.model, where));
    randomizeEveryParameter(refiner.net(), 3);
    expect(refiner.net().forward(tape, input("x", {2, 5, h, w}, 0, 1), nullptr, true));
    const Shape image{2, 1, h, w};
    const networks::RefinerOutput out =
        refiner.forward(tape, input("render", image, 0, 1), input("minus", image, 0, 1), input("plus", image, 0, 1),
                        input("previous", image, 0, 1), input("before_previous", image, 0, 1));
    expect("refined", out.refined);
    expect("residual", out.residual);
    stream.submit();
    compareWithTwin(refiner.net());
    return;
  }
  // SvDiff predicting v, SvDiff-init the noise: the twin turns either output into the noise and clean image.
  const bool initial = network == Network::SvDiffInit;
  if (!initial) config_.options["prediction"] = "v";
  const int samples = initial ? 2 : 1, conditions = initial ? 2 : 5;
  const networks::DiffusionSettings diffusion = networks::diffusionSettings(config_);
  networks::SideViewSynthesizer synthesizer(context(), models::ddpmUNetFromJson(config_.model, where), samples,
                                            conditions, diffusion.prediction);
  randomizeEveryParameter(synthesizer.net(), 4);
  expect("y", synthesizer.net().forward(tape, input("x", {2, samples + conditions, h, w}, -1, 1),
                                        given("t", {2}, {3, 917})));
  const Var noisy = input("noisy", {2, samples, h, w}, -1, 1);
  const Var condition = input("condition", {2, conditions, h, w}, 0, 1);
  const Var prediction = synthesizer.predict(tape, noisy, condition, given("steps", {2}, {41, 650}));
  const diffusion::StepFactorTensors factors(context(), 2);
  factors.upload(diffusion::stepFactors(diffusion.schedule, std::vector<int>{41, 650}));
  expect("prediction", prediction);
  expect("eps", diffusion::noiseFromPrediction(tape, diffusion.prediction, noisy, prediction, factors));
  expect("clean", diffusion::cleanFromPrediction(tape, diffusion.prediction, noisy, prediction, factors));
  stream.submit();
  compareWithTwin(synthesizer.net());
}

INSTANTIATE_TEST_SUITE_P(EveryNetwork, PyTorchTwinTest, ::testing::ValuesIn(networks::allNetworks()),
                         [](const ::testing::TestParamInfo<Network>& param) {
                           std::string name = networks::networkName(param.param);
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

}  // namespace
}  // namespace smokesvd::testing
