#include "pipeline/train/training_run.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "nets/io/file_io.h"
#include "nets/io/json_file.h"
#include "nets/io/safetensors.h"
#include "nets/optim/adam.h"
#include "nets/optim/checkpoint.h"
#include "nets/optim/ema.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/train/loss_log.h"
#include "pipeline/train/loss_plot.h"
#include "pipeline/train/model_weights.h"
#include "pipeline/train/training_step.h"
#include "pipeline/progress.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace fs = std::filesystem;
namespace {

// Everything a run writes into its folder; --overwrite removes exactly these.
const std::vector<std::string>& runFiles() {
  static const std::vector<std::string> files{"config.json", "checkpoint.safetensors", "loss.csv", "loss.png",
                                              "validation.csv", "run.json", "model.safetensors", "model_card.md"};
  return files;
}

nlohmann::json readJson(const fs::path& path) { return io::readJsonFile(path, "delete it or use --overwrite"); }

struct Recording {
  explicit Recording(Context& context) : stream(context), tape(stream) {}
  Stream stream;
  Tape tape;
  LossTerms terms;
};

std::string metricLine(const std::vector<Metric>& metrics) {
  std::ostringstream line;
  line.precision(4);
  for (const Metric& m : metrics) line << (line.tellp() > 0 ? ", " : "") << m.name << " " << m.value;
  return line.str();
}

void checkFinite(const LossTerms& terms, const std::vector<float>& values, int64_t step) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw Error("training step " + std::to_string(step + 1) + ": loss term '" +
                  (i == 0 ? std::string("total") : terms.terms[i - 1].first) +
                  "' is not finite; lower the learning rate, or run with SMOKESVD_CHECK=1 to find the first bad kernel");
}

}  // namespace

diffusion::Gaussian stepRandom(uint64_t seed, int64_t step) {
  return diffusion::Gaussian(seed * 0x9e3779b97f4a7c15ull ^ (static_cast<uint64_t>(step) + 0x632be59bd9b4e019ull));
}

TrainingResult runTraining(Context& context, StageTrainer& trainer, const networks::NetworkConfig& config,
                           const TrainingOptions& options) {
  const networks::TrainSettings& t = config.train;
  if (t.checkpointEvery % t.logEvery != 0)
    throw Error(config.source + " [train]: 'checkpoint_every' must be a multiple of 'log_every', so that a resumed run "
                "logs what an uninterrupted one logs");
  const fs::path& out = options.out;
  if (fs::exists(out) && !fs::is_directory(out)) throw Error(out.string() + ": exists and is not a folder");
  fs::create_directories(out);
  const fs::path checkpointPath = out / "checkpoint.safetensors", modelPath = out / "model.safetensors";
  const nlohmann::json configJson = toJson(config);

  if (options.overwrite) {
    for (const std::string& name : runFiles()) fs::remove(out / name);
  } else if (fs::exists(out / "config.json")) {
    if (!options.resume)
      throw Error(out.string() + ": holds a training run; --resume continues it, --overwrite discards it");
    if (readJson(out / "config.json") != configJson)
      throw Error(out.string() + ": its run was trained with another config (config.json differs); "
                  "resume with the same config, or --overwrite");
  }
  io::writeJsonFile(out / "config.json", configJson);

  TrainingResult result;
  if (options.resume && fs::exists(modelPath) && fs::exists(out / "run.json") &&
      readJson(out / "run.json").value("complete", false)) {
    const nlohmann::json run = readJson(out / "run.json");
    result.steps = run.value("steps", int64_t{0});
    result.seconds = run.value("seconds", 0.0);
    result.complete = true;
    return result;
  }

  modules::Module& model = trainer.model();
  const NamedParameters parameters = model.namedParameters();
  optim::Adam adam(context, parameters, adamWOptions(t));
  optim::GradClip clip(context, t.clip);
  // The EMA's shadows start as copies of the weights the run starts from, so they are made after --init.
  if (!options.initWeights.empty()) loadWeightsFor(options.initWeights, model, config);
  optim::Ema ema(context, parameters, t.ema);
  int64_t start = 0;
  double secondsBefore = 0;
  if (options.resume && fs::exists(checkpointPath)) {
    std::map<std::string, std::string> meta;
    try {
      meta = optim::loadCheckpoint(checkpointPath, parameters, adam, &ema);
    } catch (const Error& error) {
      throw Error(std::string(error.what()) + " (delete " + checkpointPath.string() + " or use --overwrite to start afresh)");
    }
    start = adam.steps();
    secondsBefore = meta.count("seconds") ? std::stod(meta.at("seconds")) : 0.0;
  }

  std::vector<std::unique_ptr<Recording>> recordings(trainer.variants().size());
  auto recording = [&](int variant) -> Recording& {
    auto& slot = recordings.at(static_cast<std::size_t>(variant));
    if (!slot) {
      slot = std::make_unique<Recording>(context);
      slot->terms = recordTrainingStep(slot->tape, trainer, variant, parameters, {adam, clip, ema});
    }
    return *slot;
  };

  std::vector<std::string> lossColumns{"step", "seconds", "lr", "total"};
  {
    diffusion::Gaussian probe = stepRandom(options.seed, start);
    const int variant = trainer.prepare(start, probe);
    for (const auto& [name, term] : recording(variant).terms.terms) lossColumns.push_back(name);
  }
  CsvLog losses(out / "loss.csv", lossColumns, start > 0 ? start : -1);
  std::unique_ptr<CsvLog> validationLog;

  auto validate = [&](int64_t stepsDone) {
    Stream swap(context);
    std::vector<Tensor> backup;
    for (const auto& [name, p] : parameters) {
      backup.emplace_back(context, p->value.shape());
      swap.copy(p->value, backup.back());
    }
    ema.copyToParameters(swap);
    swap.submit();
    std::vector<Metric> metrics = trainer.validate();
    Stream restore(context);
    for (std::size_t i = 0; i < parameters.size(); ++i) restore.copy(backup[i], parameters[i].second->value);
    restore.submit();
    if (!validationLog) {
      std::vector<std::string> columns{"step"};
      for (const Metric& m : metrics) columns.push_back(m.name);
      validationLog = std::make_unique<CsvLog>(out / "validation.csv", columns, start > 0 ? start : -1);
    }
    std::vector<double> row{static_cast<double>(stepsDone)};
    for (const Metric& m : metrics) row.push_back(m.value);
    validationLog->append(row);
    return metrics;
  };

  Progress progress(t.steps, start, t.logEvery, options.quiet);
  const auto began = std::chrono::steady_clock::now();
  auto seconds = [&] { return secondsBefore + std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count(); };
  std::vector<double> sums(lossColumns.size() - 3, 0.0);
  int64_t summed = 0;
  const int64_t end = options.stopAfter >= 0 ? std::min(t.steps, start + options.stopAfter) : t.steps;
  for (int64_t step = start; step < end; ++step) {
    diffusion::Gaussian random = stepRandom(options.seed, step);
    Recording& r = recording(trainer.prepare(step, random));
    if (r.terms.terms.size() + 4 != lossColumns.size())
      throw Error("trainer: every variant must report the same loss terms");
    r.stream.submit();
    std::vector<float> values{r.terms.total->value.download()[0]};
    for (const auto& [name, term] : r.terms.terms) values.push_back(term->value.download()[0]);
    checkFinite(r.terms, values, step);
    for (std::size_t i = 0; i < values.size(); ++i) sums[i] += values[i];
    ++summed;
    const int64_t done = step + 1;
    char detail[64];
    std::snprintf(detail, sizeof detail, "loss %.3e", static_cast<double>(values[0]));
    progress.update(done, detail);
    if (done % t.logEvery == 0 || done == t.steps) {
      std::vector<double> row{static_cast<double>(done), seconds(), adam.options().schedule.at(step)};
      for (const double s : sums) row.push_back(s / static_cast<double>(summed));
      losses.append(row);
      std::fill(sums.begin(), sums.end(), 0.0);
      summed = 0;
    }
    if (done % t.validateEvery == 0 || done == t.steps) {
      result.validation = validate(done);
      if (!options.quiet) {
        progress.finish();
        std::fprintf(stderr, "validation at step %lld: %s\n", static_cast<long long>(done), metricLine(result.validation).c_str());
      }
    }
    const bool stopping = options.stop != nullptr && options.stop->load() && done % t.logEvery == 0;
    if (done % t.checkpointEvery == 0 || done == t.steps || stopping) {
      optim::saveCheckpoint(checkpointPath, parameters, adam, &ema,
                            {{"network", networks::networkName(config.network)}, {"seconds", std::to_string(seconds())}});
      plotLosses(out / "loss.png", losses, 3);
      io::writeJsonFile(out / "run.json", {{"complete", false}, {"steps", done}, {"seconds", seconds()}});
    }
    result.stepsThisCall = done - start;
    result.steps = done;
    if (stopping && done < t.steps) {
      result.stopped = true;
      break;
    }
  }
  progress.finish();
  result.seconds = seconds();
  result.steps = std::max(result.steps, start);
  if (result.steps < t.steps) return result;

  const std::string flops = std::to_string(trainer.forwardFlops() * 1e-9);
  io::writeSafetensors(modelPath, io::downloadNamed(ema.namedShadows()),
                       {{"network", networks::networkName(config.network)}, {"preset", config.preset},
                        {"steps", std::to_string(result.steps)}, {"format", "smokesvd-model"}});
  std::ostringstream card;
  card << "# " << networks::networkName(config.network) << " (" << config.preset << " preset)\n\n"
       << "- Architecture: `config.json` section `model` (docs/models.md); " << model.parameterCount()
       << " parameters; " << flops << " GFLOP per forward pass.\n"
       << "- Data: " << trainer.dataSummary() << ".\n"
       << "- Training: " << result.steps << " steps of AdamW (lr " << t.lr << ", warm-up " << t.warmup
       << ", cosine to " << t.lr * t.minLrFraction << ", clip " << t.clip << "), batch " << t.batch << ", seed "
       << options.seed << "; weights are the EMA (decay " << t.ema << ")"
       << (options.initWeights.empty() ? std::string() : "; initialised from " + options.initWeights.string()) << ".\n"
       << "- Time: " << formatDuration(result.seconds) << " on " << context.info().name << ".\n"
       << "- Validation on held-out scenes (the last): " << metricLine(result.validation) << ".\n";
  io::writeTextFileAtomically(out / "model_card.md", card.str());
  io::writeJsonFile(out / "run.json", {{"complete", true}, {"steps", result.steps}, {"seconds", result.seconds}});
  fs::remove(checkpointPath);
  result.complete = true;
  return result;
}

}  // namespace smokesvd::train
