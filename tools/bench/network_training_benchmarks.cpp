// Training-step benchmarks of the method's networks, `train/<network>/<preset>` for the six networks at
// the tiny, small and paper presets: the step `smokesvd train` records (the trainer's sample, forward,
// renders and losses, backward, clip, AdamW, EMA; pipeline/train/training_step.h), batch as the
// preset's built-in config says, each variant the trainer records (lit or unlit look, a guided or an
// unguided diffusion step, true or G_rho densities) measured on its own.
//
// The data are three scenes simulated at the preset into a scratch folder (two for training, one unlit and
// one lit, and one held out), the networks a trainer runs frozen (G_rho for NvRef and SvDiff, G_u for SvDiff's guidance, the
// fine G_rho for G_u's fine-tuning) are trained one step there first: the step's cost depends on their
// architectures, not on their weights. FLOPs are the whole step's, counted on its recording
// (modules::FlopCounter): every convolution and linear layer it runs, the trained network's and the frozen
// ones', forward, and each backward pass it records (to the inputs, to the weights); renders, advection,
// activations and the optimiser are memory-bound and in the time only. The shape column gives the trained
// network's share (its layers' forward and backward FLOPs, its passes under NoGrad included); a table after
// the timings gives one forward pass of the trained network alone and the whole step, in GFLOP. A step is
// long, so each is timed over 1 warm-up and at most 5 runs. Where the device cannot hold a step (a tensor
// past its buffer limit, memory exhausted) the line says so instead of a time.
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "nets/io/temporary_folder.h"
#include "nets/modules/flop_counter.h"
#include "nets/optim/adam.h"
#include "nets/optim/ema.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/dataset/scene_dataset.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/preset.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "pipeline/train/make_trainer.h"
#include "pipeline/train/training_run.h"
#include "pipeline/train/training_step.h"
#include "runtime/error.h"
#include "tools/bench/bench.h"
#include "tools/bench/network_benchmarks.h"

namespace smokesvd::bench {
namespace {

namespace fs = std::filesystem;

constexpr int kSceneFrames = 10;
constexpr int kScenes = 3;
constexpr int kValidationEvery = 3;  // of the three scenes, the third is held out
constexpr int64_t kProbedSteps = 48;  // variants are looked for among the first and the last steps of a config

networks::NetworkConfig benchConfig(const std::string& presetName, networks::Network network) {
  networks::NetworkConfig config = networks::defaultNetworkConfig(presetName, network);
  config.data.validationEvery = kValidationEvery;
  config.train.validationSamples = 1;
  return config;
}

// The scenes and frozen networks of one preset, made the first time a benchmark of that preset asks.
class PresetScratch {
 public:
  PresetScratch(Context& context, const std::string& presetName) {
    const Preset& scenePreset = preset(presetName);
    for (int i = 0; i < kScenes; ++i) {
      sim::Scene scene = sim::randomScene(7100 + static_cast<uint64_t>(i), scenePreset.grid, kSceneFrames);
      scene.render.enabled = false;
      // The first training scene unlit, the second lit (as 35 % of simulate's scenes are), so that the
      // steps of both looks come up among the probed steps.
      scene.render.lightDirection.reset();
      if (i == 1) {
        scene.render.lightDirection = Vec3{0.4, 0.7, -0.6};
        scene.render.lightIntensity = 0.7;
        scene.render.ambient = 0.35;
        scene.render.lightAbsorption = scene.render.absorption;
      }
      sim::runScene(context, scene, folder_.path() / "data" / ("scene_000" + std::to_string(i)), {.render = false});
    }
    dataset::DatasetOptions options;
    options.validationEvery = kValidationEvery;
    data_ = std::make_unique<dataset::SceneDataset>(folder_.path() / "data", scenePreset, options);
    for (const networks::Network frozen : {networks::Network::GrhoCoarse, networks::Network::GrhoFine, networks::Network::Gu}) {
      networks::NetworkConfig config = benchConfig(presetName, frozen);
      config.train.steps = 1;
      config.train.warmup = 0;
      config.train.logEvery = config.train.checkpointEvery = config.train.validateEvery = 1;
      if (config.options.contains("finetune_steps")) config.options["finetune_steps"] = 0;
      const auto trainer = train::makeTrainer(context, config, *data_, models());
      train::TrainingOptions run;
      run.out = models() / networks::networkName(frozen);
      run.quiet = true;
      train::runTraining(context, *trainer, config, run);
    }
  }
  const dataset::SceneDataset& data() const { return *data_; }
  fs::path models() const { return folder_.path() / "models"; }

 private:
  io::TemporaryFolder folder_{"bench"};
  std::unique_ptr<dataset::SceneDataset> data_;
};

// The scratch of `presetName`, made once; a preset the device cannot simulate or train is not retried.
PresetScratch& scratch(Context& context, const std::string& presetName) {
  static std::map<std::string, std::unique_ptr<PresetScratch>> made;
  static std::map<std::string, std::string> failed;
  if (failed.count(presetName)) throw Error(failed.at(presetName));
  auto& slot = made[presetName];
  if (!slot) {
    try {
      slot = std::make_unique<PresetScratch>(context, presetName);
    } catch (const Error& error) {
      failed[presetName] = std::string("preparing the ") + presetName + " scenes and frozen networks: " + error.what();
      throw Error(failed.at(presetName));
    }
  }
  return *slot;
}

// Every variant of the trainer's step, each after the sample of the first probed step that asks for it.
void measureNetwork(BenchContext& b, const std::string& base, networks::Network network,
                    const std::string& presetName) {
  Context& context = b.context();
  try {
    const networks::NetworkConfig config = benchConfig(presetName, network);
    PresetScratch& s = scratch(context, presetName);
    const auto trainer = train::makeTrainer(context, config, s.data(), s.models());
    const networks::TrainSettings& t = config.train;
    const NamedParameters parameters = trainer->model().namedParameters();
    const optim::Adam adam(context, parameters, train::adamWOptions(t));
    const optim::GradClip clip(context, t.clip);
    const optim::Ema ema(context, parameters, t.ema);
    const GridSize grid = preset(presetName).grid;
    const std::string batchAndGrid = "batch " + std::to_string(t.batch) + ", " + std::to_string(grid.x) + "x" +
                                     std::to_string(grid.y) + "x" + std::to_string(grid.z);
    const double forwardFlops = trainer->forwardFlops();
    const std::vector<std::string> variants = trainer->variants();
    std::vector<bool> measured(variants.size(), false);
    const LongRunTiming timing(b);
    for (int64_t probe = 0; probe < 2 * kProbedSteps; ++probe) {
      const int64_t step = probe < kProbedSteps ? probe : t.steps - 2 * kProbedSteps + probe;
      if (step < 0 || step >= t.steps) continue;
      diffusion::Gaussian random = train::stepRandom(0, step);
      const int variant = trainer->prepare(step, random);
      if (measured.at(static_cast<std::size_t>(variant))) continue;
      measured[static_cast<std::size_t>(variant)] = true;
      const std::string name = variants.size() == 1 ? base : base + ":" + variants[static_cast<std::size_t>(variant)];
      double stepFlops = 0, trainedFlops = 0;  // counted when the measurement records the step
      b.measureStep(name, batchAndGrid, 0, {}, [&](Stream& stream) {
        Tape tape(stream);
        const modules::FlopCounter counter;
        train::recordTrainingStep(tape, *trainer, variant, parameters, {adam, clip, ema});
        stepFlops = counter.flops() + counter.backwardFlops();
        trainedFlops = counter.trainedFlops();
      });
      Measurement& m = b.last();
      m.flops = stepFlops;
      m.forwardFlops = forwardFlops;
      if (stepFlops > 0) m.shape += ", net " + std::to_string(static_cast<int>(std::lround(100 * trainedFlops / stepFlops))) + "%";
    }
  } catch (const Error& error) {
    addNotRun(b, base, error.what());
  } catch (const std::bad_alloc&) {
    addNotRun(b, base, "out of host memory");
  }
}

const bool registered = registerNetworkBenchmarks("train", measureNetwork);

}  // namespace
}  // namespace smokesvd::bench
