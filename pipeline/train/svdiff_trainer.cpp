#include "pipeline/train/svdiff_trainer.h"

#include <cmath>
#include <tuple>

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/functional/reduce_axes.h"
#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/differentiable/physics.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/trained_model.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

Var constant(Tape& tape, float value) { return variable(Tensor::fromHost(tape.context(), {1}, std::vector<float>{value})); }
Var zero(Tape& tape) { return constant(tape, 0.0f); }

}  // namespace

SvDiffTrainer::SvDiffTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
                             const std::filesystem::path& models, bool initial)
    : context_(context), config_(config), data_(data), initial_(initial),
      schedule_(networks::diffusionSettings(config).schedule),
      synthesizer_(std::move(*networks::makeSideViewSynthesizer(context, config))),
      look_(context), factors_(context, config.train.batch) {
  const std::string lossWhere = config.source + " [loss]", optionsWhere = config.source + " [options]";
  const Preset& p = data.preset();
  if (initial) {
    models::requireKnownKeys(config.loss, {"noise", "image", "row_sum"}, lossWhere);
    models::requireKnownKeys(config.options, {"diffusion_steps", "beta_start", "beta_end", "prediction",
                                              "guidance_threshold", "coarse_model", "guidance"},
                             optionsWhere);
  } else {
    models::requireKnownKeys(config.loss, {"noise", "image", "row_sum", "velocity"}, lossWhere);
    models::requireKnownKeys(config.options, {"diffusion_steps", "beta_start", "beta_end", "prediction",
                                              "guidance_threshold", "coarse_model", "frames", "multi_frame",
                                              "multi_frame_steps", "guidance", "velocity_model", "init_history",
                                              "init_model"},
                             optionsWhere);
    frames_ = static_cast<int>(networks::integer(config.options, "frames", optionsWhere));
    multiFrame_ = networks::flag(config.options, "multi_frame", optionsWhere);
    if (config.options.contains("multi_frame_steps")) {
      const std::string steps = networks::text(config.options, "multi_frame_steps", optionsWhere);
      if (steps != "guided" && steps != "all")
        throw Error(optionsWhere + ": 'multi_frame_steps' must be \"guided\" or \"all\", not \"" + steps + "\"");
      multiFrameEveryStep_ = steps == "all";
    }
    if (frames_ < 1) throw Error(optionsWhere + ": 'frames' must be at least 1");
    if (config.options.contains("init_history")) initHistory_ = networks::number(config.options, "init_history", optionsWhere);
    if (!(initHistory_ >= 0 && initHistory_ <= 1)) throw Error(optionsWhere + ": 'init_history' must be a probability in [0, 1]");
    if (config.train.batch != 1) throw Error(config.source + " [train]: SvDiff trains with batch 1 (one frame sequence)");
  }
  weights_ = {networks::number(config.loss, "noise", lossWhere), networks::number(config.loss, "image", lossWhere),
              networks::number(config.loss, "row_sum", lossWhere),
              initial ? 0.0 : networks::number(config.loss, "velocity", lossWhere)};
  guidance_ = networks::flag(config.options, "guidance", optionsWhere);
  threshold_ = static_cast<int>(networks::integer(config.options, "guidance_threshold", optionsWhere));
  if (threshold_ < 1 || threshold_ >= schedule_.steps())
    throw Error(optionsWhere + ": 'guidance_threshold' must be in [1, diffusion_steps)");
  batch_ = config.train.batch;

  frontSideViews_ = render::uploadViews(context, std::vector<Camera>{networks::orbitCameraAt(p, 0), networks::orbitCameraAt(p, 90)});
  sideView_ = render::uploadViews(context, std::vector<Camera>{networks::orbitCameraAt(p, 90)});
  if (!initial || guidance_) {
    if (networks::text(config.options, "coarse_model", optionsWhere) != "grho-coarse")
      throw Error(optionsWhere + ": 'coarse_model' must be \"grho-coarse\"");
  }
  if (!initial) {
    coarse_ = networks::loadFrozenDensityGenerator(context, models, networks::Network::GrhoCoarse, p);
    if (guidance_ && weights_.velocity > 0) {
      if (networks::text(config.options, "velocity_model", optionsWhere) != "gu")
        throw Error(optionsWhere + ": 'velocity_model' must be \"gu\"");
      const networks::TrainedModel gu = networks::findTrainedModel(models, networks::Network::Gu, p);
      velocity_ = std::make_unique<networks::VelocityGenerator>(
          context, models::unet3PlusFromJson(gu.config.model, gu.config.source + " [model]"), p);
      networks::loadTrainedWeights(gu, velocity_->net());
      networks::freeze(velocity_->net());
    }
    if (initHistory_ > 0) {
      if (networks::text(config.options, "init_model", optionsWhere) != "svdiff-init")
        throw Error(optionsWhere + ": 'init_model' must be \"svdiff-init\" (needed by 'init_history')");
      const networks::TrainedModel svi = networks::findTrainedModel(models, networks::Network::SvDiffInit, p);
      init_ = networks::makeSideViewSynthesizer(context, svi.config);
      networks::loadTrainedWeights(svi, init_->net());
      networks::freeze(init_->net());
      const diffusion::NoiseSchedule initSchedule = networks::diffusionSettings(svi.config).schedule;
      const int last = initSchedule.steps() - 1;
      initNoise_ = variable(Tensor(context, {1, 2, p.imageHeight, p.imageWidth}));
      initSteps_ = variable(Tensor::fromHost(context, {1}, std::vector<float>{static_cast<float>(last)}));
      initFactors_ = std::make_unique<diffusion::StepFactorTensors>(context, 1);
      initFactors_->upload(diffusion::stepFactors(initSchedule, std::vector<int>{last}));
    }
  }
  const int volumes = initial ? 2 * batch_ : frames_ + 2;
  for (int i = 0; i < volumes; ++i) densities_.push_back(variable(Tensor(context, p.grid.volume())));
  if (initial)
    noise_.push_back(variable(Tensor(context, {batch_, 2, p.imageHeight, p.imageWidth})));
  else
    for (int i = 0; i < frames_; ++i) noise_.push_back(variable(Tensor(context, {1, 1, p.imageHeight, p.imageWidth})));
  steps_ = variable(Tensor(context, {batch_}));
  synthesizer_.net().initialize(initial ? 0x737669 : 0x7376);
}

std::vector<std::string> SvDiffTrainer::variants() const {
  std::vector<std::string> names{"unguided-unlit", "unguided-lit", "guided-unlit", "guided-lit"};
  if (initHistory_ > 0)
    for (int i = 0; i < 4; ++i) names.push_back(names[static_cast<std::size_t>(i)] + "-init-history");
  return names;
}

int SvDiffTrainer::framesPerSample() const { return initial_ ? 2 : frames_ + 2; }

int SvDiffTrainer::upload(const dataset::SceneEntry& scene, const std::vector<int>& frames, const Augmentation& a,
                          int step, diffusion::Gaussian& random) {
  for (std::size_t i = 0; i < frames.size(); ++i) densities_[i]->value.upload(augmentedDensity(data_, scene, frames[i], a));
  for (const Var& n : noise_) n->value.upload(random.values(static_cast<std::size_t>(n->value.numel())));
  if (initNoise_) initNoise_->value.upload(random.values(static_cast<std::size_t>(initNoise_->value.numel())));
  steps_->value.upload(std::vector<float>(static_cast<std::size_t>(batch_), static_cast<float>(step)));
  factors_.upload(diffusion::stepFactors(schedule_, std::vector<int>(static_cast<std::size_t>(batch_), step)));
  return look_.upload(augmentedLook(data_, scene, a));
}

int SvDiffTrainer::prepare(int64_t, diffusion::Gaussian& random) {
  const Augmentation a = drawAugmentation(config_.data, random);
  const bool guided = guidance_ && random.uniform() < static_cast<double>(threshold_) / schedule_.steps();
  const double u = random.uniform();
  const int T = schedule_.steps();
  int step = guidance_ ? (guided ? static_cast<int>(u * threshold_) : threshold_ + static_cast<int>(u * (T - threshold_)))
                       : static_cast<int>(u * T);
  step = std::min(step, T - 1);
  std::vector<int> frames;
  const dataset::SceneEntry* scene = nullptr;
  if (initial_) {
    const FrameDraw first = drawFrames(data_.training(), 2, 0, random);
    scene = first.scene;
    frames = {first.frame, first.frame + 1};
    for (int b = 1; b < batch_; ++b) {
      const int t = std::min(scene->frames - 2, static_cast<int>(random.uniform() * (scene->frames - 1)));
      frames.push_back(t);
      frames.push_back(t + 1);
    }
  } else {
    const FrameDraw draw = drawFrames(data_.training(), frames_, 2, random);
    scene = draw.scene;
    for (int k = -2; k < frames_; ++k) frames.push_back(draw.frame + k);
  }
  const int look = upload(*scene, frames, a, step, random);
  const bool initHistory = initHistory_ > 0 && random.uniform() < initHistory_;  // drawn last: the sample stays the same
  return look + (guided ? 2 : 0) + (initHistory ? 4 : 0);
}

std::pair<Var, Var> SvDiffTrainer::initEstimates(Tape& tape, const Var& front0, const Var& front1) {
  const Var predicted = init_->predict(tape, initNoise_, fn::concatChannels(tape, {front0, front1}), initSteps_);
  const Var w = networks::toImageRange(
      tape, diffusion::cleanFromPrediction(tape, init_->prediction(), initNoise_, predicted, *initFactors_));
  // clamp(w, 0, 1) = 1 - relu(1 - relu(w))
  const Var one = constant(tape, 1.0f);
  auto oneMinus = [&](const Var& x) { return fn::broadcastBinary(tape, ops::BinaryOp::Add, fn::scale(tape, x, -1.0f), one); };
  const Var clamped = oneMinus(fn::relu(tape, oneMinus(fn::relu(tape, w))));
  return {fn::sliceChannels(tape, clamped, 0, 1), fn::sliceChannels(tape, clamped, 1, 2)};
}

SvDiffTrainer::FrameErrors SvDiffTrainer::frameErrors(Tape& tape, const Var& clean, const Var& noise, const Var& noisy,
                                                      const Var& predicted) {
  const diffusion::Prediction prediction = synthesizer_.prediction();
  return {fn::mseLoss(tape, diffusion::noiseFromPrediction(tape, prediction, noisy, predicted, factors_), noise),
          fn::mseLoss(tape, diffusion::cleanFromPrediction(tape, prediction, noisy, predicted, factors_), clean)};
}

SvDiffTrainer::FrontSide SvDiffTrainer::frontSide(Tape& tape, const Var& density, const render::RenderSettings& settings) {
  const Var both = diff::render(tape, density, frontSideViews_, settings);
  return {fn::sliceBatch(tape, both, 0, 1), fn::sliceBatch(tape, both, 1, 2)};
}

LossTerms SvDiffTrainer::recordInitial(Tape& tape, bool guided, const render::RenderSettings& settings, FrameErrors* errors) {
  const Preset& p = data_.preset();
  Var sides, fronts;
  {
    // Each density's front and side renders [2, 1, H, W], gathered end to end by transfer commands into
    // [densities, 2, H, W], then the two views sliced out: two dispatches, not one per image.
    NoGrad noGrad(tape);
    std::vector<Tensor> renders;
    std::vector<int64_t> offsets;
    for (const Var& density : densities_) {
      offsets.push_back(static_cast<int64_t>(renders.size()) * 2 * p.imageHeight * p.imageWidth);
      renders.push_back(diff::render(tape, density, frontSideViews_, settings)->value);
    }
    Tensor gathered(tape.context(), {static_cast<int64_t>(renders.size()), 2, p.imageHeight, p.imageWidth});
    tape.stream().gather(renders, offsets, gathered);
    const Var both = variable(gathered);
    const Shape batch{batch_, 2, p.imageHeight, p.imageWidth};
    fronts = fn::reshape(tape, fn::sliceChannels(tape, both, 0, 1), batch);
    sides = fn::reshape(tape, fn::sliceChannels(tape, both, 1, 2), batch);
  }
  const Var clean = networks::toDiffusionRange(tape, sides);
  const Var noisy = diffusion::addNoise(tape, clean, noise_[0], factors_);
  const diffusion::Prediction prediction = synthesizer_.prediction();
  const Var predicted = synthesizer_.predict(tape, noisy, fronts, steps_);
  const Var target = diffusion::predictionTarget(tape, prediction, clean, noise_[0], factors_);
  if (errors) *errors = frameErrors(tape, clean, noise_[0], noisy, predicted);
  LossTerms terms;
  terms.terms.emplace_back("noise", fn::scale(tape, fn::mseLoss(tape, predicted, target), static_cast<float>(weights_.noise)));
  if (guided) {
    const Var estimate = diffusion::cleanFromPrediction(tape, prediction, noisy, predicted, factors_);
    terms.terms.emplace_back("image", fn::scale(tape, fn::mseLoss(tape, estimate, clean), static_cast<float>(weights_.image)));
    terms.terms.emplace_back("row_sum", fn::scale(tape, fn::rowSumLoss(tape, networks::toImageRange(tape, estimate), fronts),
                                                  static_cast<float>(weights_.rowSum)));
  } else {
    terms.terms.emplace_back("image", zero(tape));
    terms.terms.emplace_back("row_sum", zero(tape));
  }
  addUpTotal(tape, terms);
  return terms;
}

LossTerms SvDiffTrainer::recordSequence(Tape& tape, bool guided, bool initHistory, const render::RenderSettings& settings,
                                         FrameErrors* errors) {
  struct Conditioned {
    Var side, render;  // the synthesised (or true) side view and the side render of its coarse density
  };
  std::vector<FrontSide> truth;
  Conditioned beforePrevious, previous;
  Var previousDensity;
  auto coarse = [&](const Var& front, const Var& side) {
    return coarse_->forward(tape, coarse_->slotImages(tape, {{networks::kFrontSlot, front}, {networks::kSideSlot, side}}),
                            variable(Tensor::fromHost(tape.context(), {networks::kSlots}, [] {
                              std::vector<float> p(networks::kSlots, 0.0f);
                              p[networks::kFrontSlot] = p[networks::kSideSlot] = 1.0f;
                              return p;
                            }())))
        .density;
  };
  auto sideRender = [&](const Var& density) { return diff::render(tape, density, sideView_, settings); };
  {
    NoGrad noGrad(tape);
    for (const Var& density : densities_) truth.push_back(frontSide(tape, density, settings));
    Var side0 = truth[0].side, side1 = truth[1].side;
    if (initHistory) std::tie(side0, side1) = initEstimates(tape, truth[0].front, truth[1].front);
    const Var density0 = coarse(truth[0].front, side0), density1 = coarse(truth[1].front, side1);
    beforePrevious = {side0, sideRender(density0)};
    previous = {side1, sideRender(density1)};
    previousDensity = density1;
  }
  const bool chained = multiFrame_ && (guided || multiFrameEveryStep_);
  const int frames = chained ? frames_ : 1;
  std::vector<Var> noise, image, rowSum, velocity;
  for (int i = 0; i < frames; ++i) {
    const FrontSide& now = truth[static_cast<std::size_t>(i + 2)];
    const Var clean = networks::toDiffusionRange(tape, now.side);
    const Var condition =
        fn::concatChannels(tape, {now.front, previous.side, previous.render, beforePrevious.side, beforePrevious.render});
    const Var& eps = noise_[static_cast<std::size_t>(i)];
    const Var noisy = diffusion::addNoise(tape, clean, eps, factors_);
    const Var predicted = synthesizer_.predict(tape, noisy, condition, steps_);
    noise.push_back(fn::mseLoss(tape, predicted, diffusion::predictionTarget(tape, synthesizer_.prediction(), clean, eps, factors_)));
    if (errors && i == 0) *errors = frameErrors(tape, clean, eps, noisy, predicted);
    const bool last = i + 1 == frames;
    if (!guided && last) break;
    const Var estimate = diffusion::cleanFromPrediction(tape, synthesizer_.prediction(), noisy, predicted, factors_);
    const Var side = networks::toImageRange(tape, estimate);
    if (guided) {
      image.push_back(fn::mseLoss(tape, estimate, clean));
      rowSum.push_back(fn::rowSumLoss(tape, side, now.front));
    }
    const Var density = coarse(now.front, side);
    if (guided && velocity_) {
      const Var u = velocity_->forward(tape, previousDensity, density).velocity;
      const Var divergence = diff::divergence(tape, u, physics::Staggering::Centred);
      velocity.push_back(fn::reshape(tape,
                                     fn::add(tape, fn::mean(tape, fn::mul(tape, divergence, divergence)),
                                             fn::mean(tape, diff::gradientNormSquared(tape, u))),
                                     {1}));
    }
    previousDensity = density;
    beforePrevious = previous;
    previous = {side, sideRender(density)};
  }
  auto averaged = [&](const std::vector<Var>& values, double weight) {
    if (values.empty()) return zero(tape);
    return fn::scale(tape, sumOf(tape, values), static_cast<float>(weight / static_cast<double>(values.size())));
  };
  LossTerms terms;
  terms.terms.emplace_back("noise", averaged(noise, weights_.noise));
  terms.terms.emplace_back("image", averaged(image, weights_.image));
  terms.terms.emplace_back("row_sum", averaged(rowSum, weights_.rowSum));
  terms.terms.emplace_back("velocity", averaged(velocity, weights_.velocity));
  addUpTotal(tape, terms);
  return terms;
}

LossTerms SvDiffTrainer::record(Tape& tape, int variant) {
  const render::RenderSettings settings = look_.settings(variant % 2 == 1);
  const bool guided = (variant & 2) != 0, initHistory = (variant & 4) != 0;
  return initial_ ? recordInitial(tape, guided, settings) : recordSequence(tape, guided, initHistory, settings);
}

std::vector<Metric> SvDiffTrainer::validate() {
  const int samples = config_.train.validationSamples;
  const std::vector<int> probes{25, 100, 400, 800, schedule_.steps() - 1};
  std::vector<double> noiseError(probes.size(), 0.0), cleanPsnr(probes.size(), 0.0);
  for (int k = 0; k < samples; ++k) {
    const FrameDraw draw = validationFrames(data_.validation(), k, samples, initial_ ? 2 : 1, initial_ ? 0 : 2);
    std::vector<int> frames;
    if (initial_)
      for (int b = 0; b < batch_; ++b) frames.insert(frames.end(), {draw.frame, draw.frame + 1});
    else
      for (int f = -2; f < frames_; ++f) frames.push_back(std::min(draw.frame + f, draw.scene->frames - 1));
    for (std::size_t p = 0; p < probes.size(); ++p) {
      const int step = std::min(probes[p], schedule_.steps() - 1);
      diffusion::Gaussian random(static_cast<uint64_t>(k * 7919 + p));
      const int variant = upload(*draw.scene, frames, Augmentation{}, step, random);
      Stream s(context_);
      Tape tape(s);
      NoGrad noGrad(tape);
      // One frame conditioned on the truth (the unguided recording).
      const render::RenderSettings settings = look_.settings(variant % 2 == 1);
      FrameErrors errors;
      if (initial_)
        recordInitial(tape, false, settings, &errors);
      else
        recordSequence(tape, false, false, settings, &errors);
      s.submit();
      noiseError[p] += errors.noise->value.download()[0];
      const double mse = errors.clean->value.download()[0] / 4.0;  // [-1, 1] -> [0, 1]
      cleanPsnr[p] += mse > 0 ? -10 * std::log10(mse) : 100.0;
    }
  }
  const double n = samples;
  std::vector<Metric> metrics;
  for (std::size_t p = 0; p < probes.size(); ++p) metrics.push_back({"clean_psnr_at_" + std::to_string(probes[p]), cleanPsnr[p] / n});
  for (std::size_t p = 0; p < probes.size(); ++p)
    metrics.push_back({"noise_mse_at_" + std::to_string(probes[p]), noiseError[p] / n});
  return metrics;
}

std::string SvDiffTrainer::dataSummary() const {
  return describeData(data_) + (initial_ ? "" : "; conditions and guidance through the trained grho-coarse and gu");
}

double SvDiffTrainer::forwardFlops() {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  const Preset& p = data_.preset();
  const Var noisy = variable(Tensor(context_, {1, synthesizer_.sampleChannels(), p.imageHeight, p.imageWidth}));
  const Var condition = variable(Tensor(context_, {1, synthesizer_.conditionChannels(), p.imageHeight, p.imageWidth}));
  stream.fillZero(noisy->value);
  stream.fillZero(condition->value);
  const Var steps = variable(Tensor::fromHost(context_, {1}, std::vector<float>{0.0f}));
  modules::FlopCounter counter;
  synthesizer_.predict(tape, noisy, condition, steps);
  return counter.flops();
}

}  // namespace smokesvd::train
