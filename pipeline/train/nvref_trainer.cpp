#include "pipeline/train/nvref_trainer.h"

#include <algorithm>

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/concat.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

constexpr int kBatch = 4;
// The refinement stages' names in options.stages, the validation metrics and the model card.
constexpr std::array<const char*, 3> kStageNames{"near", "mid", "far"};

const std::vector<int>& stageSlots(int stage) {
  return stage == 0 ? networks::nearSlots() : stage == 1 ? networks::midSlots() : networks::farSlots();
}

std::vector<float> knownBefore(int stage) {
  std::vector<float> known(networks::kSlots, 0.0f);
  known[networks::kFrontSlot] = known[networks::kSideSlot] = 1.0f;
  for (int s = 0; s < stage; ++s)
    for (const int v : stageSlots(s)) known[static_cast<std::size_t>(v)] = 1.0f;
  return known;
}

// options.stages: the stages drawn for training, e.g. ["near", "far"] (each once, any order).
std::vector<int> parseStages(const nlohmann::json& value, const std::string& where) {
  if (!value.is_array() || value.empty())
    throw Error(where + ": 'stages' must be a non-empty list of \"near\", \"mid\" and \"far\"");
  std::vector<int> stages;
  for (const nlohmann::json& name : value) {
    const auto found = name.is_string() ? std::find(kStageNames.begin(), kStageNames.end(), name.get<std::string>())
                                          : kStageNames.end();
    if (found == kStageNames.end())
      throw Error(where + ": 'stages' holds " + name.dump() + "; expected \"near\", \"mid\" or \"far\"");
    const int stage = static_cast<int>(found - kStageNames.begin());
    if (std::find(stages.begin(), stages.end(), stage) != stages.end()) throw Error(where + ": 'stages' names " + name.dump() + " twice");
    stages.push_back(stage);
  }
  std::sort(stages.begin(), stages.end());
  return stages;
}

std::vector<float> slotsOf(int stage) {
  std::vector<float> mask(networks::kSlots, 0.0f);
  for (const int v : stageSlots(stage)) mask[static_cast<std::size_t>(v)] = 1.0f;
  return mask;
}

}  // namespace

NvRefTrainer::Batch::Batch(Context& context, const Preset& p, int n) : views(n) {
  const std::vector<Camera> targetCameras(static_cast<std::size_t>(n), networks::orbitCameraAt(p, 0));
  const std::vector<Camera> allCameras(static_cast<std::size_t>(3 * n), networks::orbitCameraAt(p, 0));
  targets = render::uploadViews(context, targetCameras);
  targetsAndAround = render::uploadViews(context, allCameras);
  const std::vector<Camera> frontCameras(networks::kSlots, networks::orbitCameraAt(p, 0));
  fronts = render::uploadViews(context, frontCameras);
  const Shape volume = p.grid.volume();
  const Shape slotImages{networks::kSlots, 1, p.imageHeight, p.imageWidth};
  for (Frame& frame : frames) {
    frame.density = variable(Tensor(context, volume));
    frame.mirrored = variable(Tensor(context, volume));
    frame.synthesised = variable(Tensor(context, slotImages));
  }
  known = variable(Tensor(context, {networks::kSlots}));
  knownWithoutSide = variable(Tensor(context, {networks::kSlots}));
  std::vector<float> sideSlot(networks::kSlots, 0.0f);
  sideSlot[networks::kSideSlot] = 1.0f;
  sideOnly = variable(Tensor::fromHost(context, {networks::kSlots}, sideSlot));
  usePrevious = variable(Tensor(context, {n}));
  const Shape images{n, 1, p.imageHeight, p.imageWidth};
  black = variable(Tensor::fromHost(context, images, std::vector<float>(static_cast<std::size_t>(numElements(images)), 0.0f)));
  for (int s = 0; s < 3; ++s) knownAt[static_cast<std::size_t>(s)] = variable(Tensor::fromHost(context, {networks::kSlots}, knownBefore(s)));
  for (int s = 0; s < 2; ++s) stageViews[static_cast<std::size_t>(s)] = variable(Tensor::fromHost(context, {networks::kSlots}, slotsOf(s)));
}

std::vector<std::string> NvRefTrainer::variants() const {
  std::vector<std::string> names;
  for (const char* stage : {"", "-mid-stage", "-far-stage"})
    for (const char* side : {"", "-mirrored-side", "-synthesised-side"})
      for (const char* look : {"unlit", "lit"}) names.push_back(std::string(look) + side + stage);
  return names;
}

NvRefTrainer::NvRefTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
                           const std::filesystem::path& models)
    : context_(context), config_(config), data_(data),
      refiner_(context, models::unet3PlusFromJson(config.model, config.source + " [model]")), look_(context),
      batch_(context, data.preset(), kBatch) {
  const std::string lossWhere = config.source + " [loss]", optionsWhere = config.source + " [options]";
  models::requireKnownKeys(config.loss, {"mse", "l1", "mean_residual", "row_sum", "psnr_gap"}, lossWhere);
  models::requireKnownKeys(config.options,
                           {"beta", "coarse_model", "mirrored_side", "synthesised_side", "side_views", "history", "psnr_reference",
                            "earlier_views", "stages"},
                           optionsWhere);
  weights_ = {networks::number(config.loss, "mse", lossWhere), networks::number(config.loss, "l1", lossWhere),
              networks::number(config.loss, "mean_residual", lossWhere), networks::number(config.loss, "row_sum", lossWhere),
              networks::number(config.loss, "psnr_gap", lossWhere)};
  beta_ = networks::number(config.options, "beta", optionsWhere);
  if (!(beta_ > 0 && beta_ < 90)) throw Error(optionsWhere + ": 'beta' must be in (0, 90) degrees");
  if (config.options.contains("mirrored_side")) mirroredSide_ = networks::number(config.options, "mirrored_side", optionsWhere);
  if (!(mirroredSide_ >= 0 && mirroredSide_ <= 1)) throw Error(optionsWhere + ": 'mirrored_side' must be a probability in [0, 1]");
  if (config.options.contains("synthesised_side"))
    synthesisedSide_ = networks::number(config.options, "synthesised_side", optionsWhere);
  if (!(synthesisedSide_ >= 0 && synthesisedSide_ <= 1 - mirroredSide_))
    throw Error(optionsWhere + ": 'synthesised_side' must be a probability in [0, 1 - mirrored_side]");
  if (config.options.contains("side_views"))
    sideViews_.emplace(networks::text(config.options, "side_views", optionsWhere), data);
  if (synthesisedSide_ > 0 && (!sideViews_ || sideViews_->training().empty()))
    throw Error(optionsWhere + ": 'synthesised_side' needs 'side_views', a folder of SvDiff's side views of training scenes "
                               "(`smokesvd rollout --split training --keep-side-views DIR`)");
  if (config.options.contains("history")) {
    const std::string history = networks::text(config.options, "history", optionsWhere);
    if (history != "truth" && history != "coarse" && history != "self")
      throw Error(optionsWhere + ": 'history' must be \"truth\", \"coarse\" or \"self\", not \"" + history + "\"");
    history_ = history == "truth" ? History::Truth : history == "coarse" ? History::Coarse : History::Self;
  }
  if (config.options.contains("psnr_reference")) {
    const std::string reference = networks::text(config.options, "psnr_reference", optionsWhere);
    if (reference != "render" && reference != "black")
      throw Error(optionsWhere + ": 'psnr_reference' must be \"render\" or \"black\", not \"" + reference + "\"");
    psnrAgainstBlack_ = reference == "black";
  }
  if (config.options.contains("earlier_views")) {
    const std::string earlier = networks::text(config.options, "earlier_views", optionsWhere);
    if (earlier != "truth" && earlier != "coarse")
      throw Error(optionsWhere + ": 'earlier_views' must be \"truth\" or \"coarse\", not \"" + earlier + "\"");
    coarseEarlierViews_ = earlier == "coarse";
  }
  if (config.options.contains("stages")) stages_ = parseStages(config.options["stages"], optionsWhere);
  if (networks::text(config.options, "coarse_model", optionsWhere) != "grho-coarse")
    throw Error(optionsWhere + ": 'coarse_model' must be \"grho-coarse\"");
  coarse_ = networks::loadFrozenDensityGenerator(context, models, networks::Network::GrhoCoarse, data.preset());
  refiner_.net().initialize(0x6e76);
}

int NvRefTrainer::upload(Batch& batch, const dataset::SceneEntry& scene, int frame, const Augmentation& a, int stage,
                         const std::vector<int>& slots, const std::vector<float>& usePrevious, Side side) {
  const Preset& p = data_.preset();
  std::vector<Camera> targets;
  for (const int slot : slots) targets.push_back(networks::orbitCameraAt(p, networks::slotAngle(slot)));
  std::vector<Camera> all = targets;
  for (const double sign : {-1.0, 1.0})
    for (const int slot : slots) all.push_back(networks::orbitCameraAt(p, networks::slotAngle(slot) + sign * beta_));
  render::rewriteViews(batch.targets, targets);
  render::rewriteViews(batch.targetsAndAround, all);
  // With coarse earlier views the true renders are given at the input slots only; the stages add their renders.
  const std::vector<float> known = knownBefore(coarseEarlierViews_ ? 0 : stage);
  batch.known->value.upload(known);
  batch.side = side;
  batch.stage = stage;
  if (side != Side::True) {
    std::vector<float> withoutSide = known;
    withoutSide[networks::kSideSlot] = 0.0f;
    batch.knownWithoutSide->value.upload(withoutSide);
  }
  Augmentation flipped = a;
  flipped.mirror = !a.mirror;
  // The earlier frames' side views are needed only where the history is reconstructed from them.
  const int sideFrames = history_ == History::Truth ? 1 : 3;
  for (int back = 0; back < 3; ++back) {
    Frame& f = batch.frames[static_cast<std::size_t>(back)];
    f.density->value.upload(augmentedDensity(data_, scene, frame - back, a));
    if (back >= sideFrames) continue;
    if (side == Side::Mirrored) f.mirrored->value.upload(augmentedDensity(data_, scene, frame - back, flipped));
    if (side == Side::Synthesised) {
      const std::vector<float> image = sideViews_->side(scene, frame - back);
      std::vector<float> inSideSlot(image.size() * networks::kSlots, 0.0f);
      std::copy(image.begin(), image.end(), inSideSlot.begin() + static_cast<std::ptrdiff_t>(image.size() * networks::kSideSlot));
      f.synthesised->value.upload(inSideSlot);
    }
  }
  batch.usePrevious->value.upload(usePrevious);
  return look_.upload(augmentedLook(data_, scene, a));
}

int NvRefTrainer::prepare(int64_t, diffusion::Gaussian& random) {
  FrameDraw draw = drawFrames(data_.training(), 1, 2, random);
  Augmentation a = drawAugmentation(config_.data, random);
  const std::size_t drawn = static_cast<std::size_t>(random.uniform() * static_cast<double>(stages_.size()));
  const int stage = stages_[std::min(stages_.size() - 1, drawn)];
  std::vector<int> slots = stageSlots(stage);
  while (slots.size() > kBatch) slots.erase(slots.begin() + static_cast<std::ptrdiff_t>(random.uniform() * static_cast<double>(slots.size())));
  std::vector<float> usePrevious;
  for (int i = 0; i < kBatch; ++i) usePrevious.push_back(random.uniform() < 0.1 ? 0.0f : 1.0f);
  Side side = Side::True;
  if (mirroredSide_ > 0 || synthesisedSide_ > 0) {
    const double u = random.uniform();
    side = u < mirroredSide_ ? Side::Mirrored : u < mirroredSide_ + synthesisedSide_ ? Side::Synthesised : Side::True;
  }
  if (side == Side::Synthesised) {
    // A frame that SvDiff's rollout reached, as the scene was simulated. (The draws above stay, unused here,
    // so that configs without synthesised sides draw the same samples as before the option existed.)
    draw = drawFrames(sideViews_->training(), 1, sideViews_->manifest().firstFrame + 2, random);
    a = Augmentation{};
  }
  return upload(batch_, *draw.scene, draw.frame, a, stage, slots, usePrevious, side) + 2 * static_cast<int>(side) +
         (coarseEarlierViews_ ? 6 * stage : 0);
}

// The coarse G_rho's density of a frame from the views known at the batch's stage; the side slot's view is
// the mirrored front view (the front render of the mirrored density) or SvDiff's, as the sample draws it.
// With earlier_views "coarse" the earlier stages' slots hold the renders of the density of the stage before.
Var NvRefTrainer::coarseDensity(Tape& tape, Batch& batch, const Frame& frame, const render::RenderSettings& settings) {
  const Var views = diff::render(tape, frame.density, coarse_->views(), settings);
  Var known;
  switch (batch.side) {
    case Side::True: known = fn::mulSample(tape, views, batch.known); break;
    case Side::Mirrored:
      known = fn::add(tape, fn::mulSample(tape, views, batch.knownWithoutSide),
                      fn::mulSample(tape, diff::render(tape, frame.mirrored, batch.fronts, settings), batch.sideOnly));
      break;
    case Side::Synthesised: known = fn::add(tape, fn::mulSample(tape, views, batch.knownWithoutSide), frame.synthesised); break;
  }
  if (!coarseEarlierViews_) return coarse_->forward(tape, known, batch.known).density;
  Var density = coarse_->forward(tape, known, batch.knownAt[0]).density;
  for (std::size_t s = 1; s <= static_cast<std::size_t>(batch.stage); ++s) {
    known = fn::add(tape, known, fn::mulSample(tape, diff::render(tape, density, coarse_->views(), settings), batch.stageViews[s - 1]));
    density = coarse_->forward(tape, known, batch.knownAt[s]).density;
  }
  return density;
}

NvRefTrainer::Images NvRefTrainer::forward(Tape& tape, Batch& batch, const render::RenderSettings& settings) {
  Images images;
  Var minus, plus, previous, beforePrevious;
  {
    NoGrad noGrad(tape);
    const Var coarse = coarseDensity(tape, batch, batch.frames[0], settings);
    const Var all = diff::render(tape, coarse, batch.targetsAndAround, settings);
    images.render = fn::sliceBatch(tape, all, 0, batch.views);
    minus = fn::sliceBatch(tape, all, batch.views, 2 * batch.views);
    plus = fn::sliceBatch(tape, all, 2 * batch.views, 3 * batch.views);
    images.truth = diff::render(tape, batch.frames[0].density, batch.targets, settings);
    // Where a previous frame stands in for nothing (frames 0 and 1), the coarse render takes its place.
    const Var instead = fn::sub(tape, variable(Tensor::fromHost(context_, {batch.views}, std::vector<float>(static_cast<std::size_t>(batch.views), 1.0f))),
                                batch.usePrevious);
    auto standIn = [&](const Frame& frame) {
      const Var density = history_ == History::Truth ? frame.density : coarseDensity(tape, batch, frame, settings);
      Var history;
      if (history_ == History::Self) {
        // That frame refined as the first frames are (its render standing in for its own history),
        // clamped at 0 as the reconstruction clamps it.
        const Var then = diff::render(tape, density, batch.targetsAndAround, settings);
        history = fn::sliceBatch(tape, then, 0, batch.views);
        history = fn::relu(tape, refiner_.forward(tape, history, fn::sliceBatch(tape, then, batch.views, 2 * batch.views),
                                                  fn::sliceBatch(tape, then, 2 * batch.views, 3 * batch.views), history, history)
                                     .refined);
      } else {
        history = diff::render(tape, density, batch.targets, settings);
      }
      return fn::add(tape, fn::mulSample(tape, history, batch.usePrevious), fn::mulSample(tape, images.render, instead));
    };
    previous = standIn(batch.frames[1]);
    beforePrevious = standIn(batch.frames[2]);
  }
  const networks::RefinerOutput out = refiner_.forward(tape, images.render, minus, plus, previous, beforePrevious);
  images.refined = out.refined;
  images.residual = out.residual;
  return images;
}

LossTerms NvRefTrainer::record(Tape& tape, int variant) {
  // The side view (and with coarse earlier views the stage) decides which kernels the recording holds, so it
  // is part of the variant.
  batch_.side = static_cast<Side>(variant % 6 / 2);
  if (coarseEarlierViews_) batch_.stage = variant / 6;
  const Images images = forward(tape, batch_, look_.settings(variant % 2 == 1));
  LossTerms terms;
  auto weighted = [&](const char* name, double weight, const Var& loss) {
    terms.terms.emplace_back(name, fn::scale(tape, loss, static_cast<float>(weight)));
  };
  weighted("mse", weights_.mse, fn::mseLoss(tape, images.refined, images.truth));
  weighted("l1", weights_.l1, fn::l1Loss(tape, images.refined, images.truth));
  weighted("mean_residual", weights_.meanResidual, fn::meanResidualSquared(tape, images.residual));
  weighted("row_sum", weights_.rowSum, fn::rowSumLoss(tape, images.refined, images.truth));
  const Var reference = psnrAgainstBlack_ ? batch_.black : images.render;
  weighted("psnr_gap", weights_.psnrGap, fn::psnrGapLoss(tape, images.refined, images.truth, reference));
  addUpTotal(tape, terms);
  return terms;
}

std::vector<Metric> NvRefTrainer::validate() {
  const int samples = config_.train.validationSamples;
  std::vector<std::unique_ptr<Batch>> batches;
  for (int stage = 0; stage < 3; ++stage)
    batches.push_back(std::make_unique<Batch>(context_, data_.preset(), static_cast<int>(stageSlots(stage).size())));
  std::vector<Metric> metrics;
  std::vector<Side> sides{Side::True, Side::Mirrored};
  if (sideViews_ && !sideViews_->validation().empty()) sides.push_back(Side::Synthesised);
  for (const Side side : sides) {
    std::vector<double> refined(3, 0.0), unrefined(3, 0.0);
    for (int k = 0; k < samples; ++k) {
      const FrameDraw draw = side == Side::Synthesised
                                 ? validationFrames(sideViews_->validation(), k, samples, 1, sideViews_->manifest().firstFrame + 2)
                                 : validationFrames(data_.validation(), k, samples, 1, 2);
      for (int stage = 0; stage < 3; ++stage) {
        Batch& batch = *batches[static_cast<std::size_t>(stage)];
        const int variant = upload(batch, *draw.scene, draw.frame, Augmentation{}, stage, stageSlots(stage),
                                   std::vector<float>(static_cast<std::size_t>(batch.views), 1.0f), side);
        Stream stream(context_);
        Tape tape(stream);
        NoGrad noGrad(tape);
        const Images images = forward(tape, batch, look_.settings(variant == 1));
        stream.submit();
        const std::vector<float> t = images.truth->value.download(), r = images.render->value.download(),
                                 f = images.refined->value.download();
        const std::size_t pixels = t.size() / static_cast<std::size_t>(batch.views);
        for (int v = 0; v < batch.views; ++v) {
          const std::span<const float> tv(t.data() + v * pixels, pixels), rv(r.data() + v * pixels, pixels),
              fv(f.data() + v * pixels, pixels);
          refined[static_cast<std::size_t>(stage)] += psnr(fv, tv) / batch.views;
          unrefined[static_cast<std::size_t>(stage)] += psnr(rv, tv) / batch.views;
        }
      }
    }
    const std::string suffix = side == Side::Mirrored ? "_mirrored" : side == Side::Synthesised ? "_synthesised" : "";
    double gain = 0;
    for (int stage = 0; stage < 3; ++stage) gain += (refined[static_cast<std::size_t>(stage)] - unrefined[static_cast<std::size_t>(stage)]) / samples / 3;
    metrics.push_back({"psnr_gain" + suffix, gain});
    for (int stage = 0; stage < 3; ++stage) {
      metrics.push_back({std::string("psnr_refined_") + kStageNames[static_cast<std::size_t>(stage)] + suffix, refined[static_cast<std::size_t>(stage)] / samples});
      metrics.push_back({std::string("psnr_unrefined_") + kStageNames[static_cast<std::size_t>(stage)] + suffix, unrefined[static_cast<std::size_t>(stage)] / samples});
    }
  }
  return metrics;
}

std::string NvRefTrainer::dataSummary() const {
  std::string stages;
  if (stages_.size() < 3) {
    for (const int s : stages_) stages += std::string(stages.empty() ? "" : " and ") + kStageNames[static_cast<std::size_t>(s)];
    stages = "; the " + stages + " stage" + (stages_.size() > 1 ? "s" : "") + " only";
  }
  return describeData(data_) + "; coarse densities from the trained grho-coarse" + stages +
         (coarseEarlierViews_ ? ", the mid and far stages' from the renders of the stage before" : "") +
         (sideViews_ ? "; " + sideViews_->describe() : "");
}

double NvRefTrainer::forwardFlops() {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  const Preset& p = data_.preset();
  const Var image = variable(Tensor(context_, {1, 1, p.imageHeight, p.imageWidth}));
  stream.fillZero(image->value);
  modules::FlopCounter counter;
  refiner_.forward(tape, image, image, image, image, image);
  return counter.flops();
}

}  // namespace smokesvd::train
