#include "pipeline/train/grho_trainer.h"

#include <cmath>

#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/train/sample_draw.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"

namespace smokesvd::train {
namespace {

using networks::kSlots;

// [16] 1 at the given slots, 0 elsewhere; `except` inverts it.
Var slotMask(Context& context, const std::vector<int>& slots, bool except = false) {
  std::vector<float> mask(kSlots, except ? 1.0f : 0.0f);
  for (const int v : slots) mask[static_cast<std::size_t>(v)] = except ? 0.0f : 1.0f;
  return variable(Tensor::fromHost(context, {kSlots}, mask));
}

double optionalProbability(const nlohmann::json& options, const char* key, const std::string& where) {
  if (!options.contains(key)) return 0;
  const double p = networks::number(options, key, where);
  if (!(p >= 0 && p <= 1)) throw Error(where + ": '" + key + "' must be a probability in [0, 1]");
  return p;
}

}  // namespace

GrhoTrainer::GrhoTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
                         const std::filesystem::path& models)
    : context_(context), config_(config), data_(data),
      generator_(context, models::unet3PlusFromJson(config.model, config.source + " [model]"), data.preset()),
      fronts_(render::uploadViews(context, std::vector<Camera>(kSlots, networks::orbitCameraAt(data.preset(), 0)))),
      look_(context) {
  const std::string lossWhere = config.source + " [loss]", optionsWhere = config.source + " [options]";
  models::requireKnownKeys(config.loss, {"density", "render_input", "render_unseen", "deep_supervision"}, lossWhere);
  models::requireKnownKeys(config.options, {"views", "extra_view_probability", "inference_views", "mirrored_side", "coarse_model"},
                           optionsWhere);
  weights_ = {networks::number(config.loss, "density", lossWhere), networks::number(config.loss, "render_input", lossWhere),
              networks::number(config.loss, "render_unseen", lossWhere), networks::number(config.loss, "deep_supervision", lossWhere)};
  const std::string views = networks::text(config.options, "views", optionsWhere);
  if (views != "fine" && views != "coarse") throw Error(optionsWhere + ": 'views' must be \"fine\" or \"coarse\"");
  fine_ = views == "fine";
  extraViewProbability_ = networks::number(config.options, "extra_view_probability", optionsWhere);
  inferenceViews_ = optionalProbability(config.options, "inference_views", optionsWhere);
  mirroredSide_ = optionalProbability(config.options, "mirrored_side", optionsWhere);
  if (mirroredSide_ > 0 && inferenceViews_ == 0)
    throw Error(optionsWhere + ": 'mirrored_side' is a share of the inference-like samples and needs 'inference_views' > 0");
  if (inferenceViews_ > 0 || config.options.contains("coarse_model")) {
    if (!fine_) throw Error(optionsWhere + ": 'inference_views' and 'coarse_model' belong to the fine G_rho (views \"fine\")");
    if (!config.options.contains("coarse_model") || networks::text(config.options, "coarse_model", optionsWhere) != "grho-coarse")
      throw Error(optionsWhere + ": inference-like views need 'coarse_model': \"grho-coarse\"");
    coarse_ = networks::loadFrozenDensityGenerator(context, models, networks::Network::GrhoCoarse, data.preset());
  }
  const Preset& p = data.preset();
  density_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  mirrored_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  frontOnly_ = slotMask(context, {networks::kFrontSlot});
  sideOnly_ = slotMask(context, {networks::kSideSlot});
  frontAndSide_ = slotMask(context, {networks::kFrontSlot, networks::kSideSlot});
  others_ = slotMask(context, {networks::kFrontSlot, networks::kSideSlot}, true);
  presence_ = variable(Tensor(context, {kSlots}));
  sqrtInputWeights_ = variable(Tensor(context, {kSlots}));
  sqrtUnseenWeights_ = variable(Tensor(context, {kSlots}));
  generator_.net().initialize(0x67726f);
}

int GrhoTrainer::upload(const std::vector<float>& density, const std::vector<float>& mirrored,
                        const render::RenderSettings& look, const std::vector<bool>& inputs, Inputs kind) {
  density_->value.upload(density);
  inputs_ = kind;
  if (kind == Inputs::InferenceMirroredSide) mirrored_->value.upload(mirrored);
  int seen = 0;
  for (const bool in : inputs) seen += in;
  const int unseen = kSlots - seen;
  std::vector<float> presence(kSlots), in(kSlots), un(kSlots);
  for (int v = 0; v < kSlots; ++v) {
    presence[static_cast<std::size_t>(v)] = inputs[static_cast<std::size_t>(v)] ? 1.0f : 0.0f;
    in[static_cast<std::size_t>(v)] = inputs[static_cast<std::size_t>(v)] ? static_cast<float>(std::sqrt(weights_.renderInput / seen)) : 0.0f;
    un[static_cast<std::size_t>(v)] =
        !inputs[static_cast<std::size_t>(v)] && unseen > 0 ? static_cast<float>(std::sqrt(weights_.renderUnseen / unseen)) : 0.0f;
  }
  presence_->value.upload(presence);
  sqrtInputWeights_->value.upload(in);
  sqrtUnseenWeights_->value.upload(un);
  return look_.upload(look) + 2 * static_cast<int>(kind);
}

std::vector<std::string> GrhoTrainer::variants() const {
  if (!coarse_) return {"unlit", "lit"};
  return {"unlit", "lit", "unlit-inference-views", "lit-inference-views", "unlit-inference-views-mirrored-side",
          "lit-inference-views-mirrored-side"};
}

std::vector<bool> GrhoTrainer::drawCoarseViews(diffusion::Gaussian& random) const {
  // The view sets of the progressive refinement (front and side; then the near views; then the mid
  // ones), and random larger sets, each slot with a random probability.
  std::vector<bool> inputs(kSlots, false);
  inputs[networks::kFrontSlot] = inputs[networks::kSideSlot] = true;
  const double kind = random.uniform();
  if (kind < extraViewProbability_) {
    const double p = random.uniform();
    for (int v = 0; v < kSlots; ++v)
      if (random.uniform() < p) inputs[static_cast<std::size_t>(v)] = true;
    return inputs;
  }
  const double stage = (kind - extraViewProbability_) / (1.0 - extraViewProbability_);
  if (stage >= 0.5)
    for (const int v : networks::nearSlots()) inputs[static_cast<std::size_t>(v)] = true;
  if (stage >= 0.75)
    for (const int v : networks::midSlots()) inputs[static_cast<std::size_t>(v)] = true;
  return inputs;
}

int GrhoTrainer::prepare(int64_t, diffusion::Gaussian& random) {
  const FrameDraw draw = drawFrames(data_.training(), 1, 0, random);
  const Augmentation a = drawAugmentation(config_.data, random);
  std::vector<bool> inputs(kSlots, true);
  if (!fine_) inputs = drawCoarseViews(random);
  Inputs kind = Inputs::True;
  std::vector<float> mirrored;
  if (inferenceViews_ > 0 && random.uniform() < inferenceViews_) {
    kind = Inputs::InferenceTrueSide;
    if (mirroredSide_ > 0 && random.uniform() < mirroredSide_) {
      kind = Inputs::InferenceMirroredSide;
      Augmentation flipped = a;
      flipped.mirror = !a.mirror;
      mirrored = augmentedDensity(data_, *draw.scene, draw.frame, flipped);
    }
  }
  return upload(augmentedDensity(data_, *draw.scene, draw.frame, a), mirrored, augmentedLook(data_, *draw.scene, a), inputs, kind);
}

GrhoTrainer::InputViews GrhoTrainer::inputViews(Tape& tape, const Var& truth, const render::RenderSettings& settings) {
  if (inputs_ == Inputs::True) return {fn::mulSample(tape, truth, presence_), Var()};
  // The side slot holds the true side view, or the mirrored front view: the front render of the mirrored
  // density (rendered at 16 front cameras so that it lines up with the slots).
  const Var side = inputs_ == Inputs::InferenceMirroredSide ? diff::render(tape, mirrored_, fronts_, settings) : truth;
  const Var known = fn::add(tape, fn::mulSample(tape, truth, frontOnly_), fn::mulSample(tape, side, sideOnly_));
  const Var coarse = coarse_->forward(tape, known, frontAndSide_).density;
  const Var renders = diff::render(tape, coarse, generator_.views(), settings);
  return {fn::add(tape, known, fn::mulSample(tape, renders, others_)), coarse};
}

LossTerms GrhoTrainer::record(Tape& tape, int variant) {
  const render::RenderSettings settings = look_.settings(variant % 2 == 1);
  inputs_ = static_cast<Inputs>(variant / 2);
  Var truth, input;
  {
    NoGrad noGrad(tape);
    truth = diff::render(tape, density_, generator_.views(), settings);
    input = inputViews(tape, truth, settings).views;
  }
  const networks::DensityOutput out = generator_.forward(tape, input, presence_, weights_.deepSupervision > 0);
  const Var renders = diff::render(tape, out.density, generator_.views(), settings);

  LossTerms terms;
  terms.terms.emplace_back("density", fn::scale(tape, fn::mseLoss(tape, out.density, density_), static_cast<float>(weights_.density)));
  terms.terms.emplace_back("render_input", weightedViewMse(tape, renders, truth, sqrtInputWeights_));
  terms.terms.emplace_back("render_unseen", weightedViewMse(tape, renders, truth, sqrtUnseenWeights_));
  if (!out.supervision.empty()) {
    std::vector<Var> heads;
    for (const Var& head : out.supervision) heads.push_back(fn::mseLoss(tape, head, density_));
    terms.terms.emplace_back(
        "deep_supervision", fn::scale(tape, sumOf(tape, heads), static_cast<float>(weights_.deepSupervision / static_cast<double>(out.supervision.size()))));
  }
  addUpTotal(tape, terms);
  return terms;
}

GrhoTrainer::ViewErrors GrhoTrainer::evaluate(int variant) {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  const render::RenderSettings settings = look_.settings(variant % 2 == 1);
  const Var truth = diff::render(tape, density_, generator_.views(), settings);
  const InputViews in = inputViews(tape, truth, settings);
  const Var density = generator_.forward(tape, in.views, presence_).density;
  const Var renders = diff::render(tape, density, generator_.views(), settings);
  const Var coarseRenders = in.coarse ? diff::render(tape, in.coarse, generator_.views(), settings) : Var();
  stream.submit();
  const std::vector<float> t = truth->value.download(), r = renders->value.download();
  const std::vector<float> c = coarseRenders ? coarseRenders->value.download() : std::vector<float>();
  const std::vector<float> d = density->value.download(), dt = density_->value.download();
  ViewErrors e;
  const std::size_t pixels = t.size() / kSlots;
  const std::vector<float> black(pixels, 0.0f);
  for (int v = 0; v < kSlots; ++v) {
    const std::span<const float> tv(t.data() + v * pixels, pixels), rv(r.data() + v * pixels, pixels);
    e.psnr.push_back(psnr(rv, tv));
    e.blackPsnr.push_back(psnr(black, tv));
    if (!c.empty()) e.coarsePsnr.push_back(psnr(std::span<const float>(c.data() + v * pixels, pixels), tv));
  }
  double sum = 0;
  for (std::size_t i = 0; i < d.size(); ++i) sum += (static_cast<double>(d[i]) - dt[i]) * (static_cast<double>(d[i]) - dt[i]);
  e.densityRmse = std::sqrt(sum / static_cast<double>(d.size()));
  return e;
}

std::vector<Metric> GrhoTrainer::validate() {
  const int samples = config_.train.validationSamples;
  double all = 0, novel = 0, frontOnly = 0, black = 0, rmse = 0;
  // Inference-like inputs, with the true [0] and the mirrored [1] side view: the 14 other views' PSNR of
  // this network's density and of the coarse G_rho's density it was given the renders of.
  double inferenceFine[2] = {0, 0}, inferenceCoarse[2] = {0, 0};
  auto mean = [](const std::vector<double>& values, bool skipInputs) {
    double sum = 0;
    int n = 0;
    for (int v = 0; v < kSlots; ++v)
      if (!skipInputs || (v != networks::kFrontSlot && v != networks::kSideSlot)) {
        sum += values[static_cast<std::size_t>(v)];
        ++n;
      }
    return sum / n;
  };
  for (int k = 0; k < samples; ++k) {
    const FrameDraw draw = validationFrames(data_.validation(), k, samples, 1, 0);
    const std::vector<float> density = data_.density(*draw.scene, draw.frame);
    const render::RenderSettings look = data_.look(*draw.scene);
    if (fine_) {
      const std::vector<bool> every(kSlots, true);
      const ViewErrors e = evaluate(upload(density, {}, look, every, Inputs::True));
      all += mean(e.psnr, false);
      black += mean(e.blackPsnr, false);
      rmse += e.densityRmse;
      if (coarse_) {
        Augmentation flipped;
        flipped.mirror = true;
        const std::vector<float> mirrored = augmentedDensity(data_, *draw.scene, draw.frame, flipped);
        for (const Inputs kind : {Inputs::InferenceTrueSide, Inputs::InferenceMirroredSide}) {
          const ViewErrors i = evaluate(upload(density, mirrored, look, every, kind));
          const int side = kind == Inputs::InferenceMirroredSide ? 1 : 0;
          inferenceFine[side] += mean(i.psnr, true);
          inferenceCoarse[side] += mean(i.coarsePsnr, true);
        }
      }
    } else {
      std::vector<bool> inputs(kSlots, false);
      inputs[networks::kFrontSlot] = inputs[networks::kSideSlot] = true;
      const ViewErrors e = evaluate(upload(density, {}, look, inputs, Inputs::True));
      novel += mean(e.psnr, true);
      black += mean(e.blackPsnr, true);
      rmse += e.densityRmse;
      inputs[networks::kSideSlot] = false;
      frontOnly += mean(evaluate(upload(density, {}, look, inputs, Inputs::True)).psnr, true);
    }
  }
  const double n = samples;
  if (!fine_)
    return {{"psnr_novel_front_side", novel / n}, {"psnr_novel_front_only", frontOnly / n},
            {"density_rmse", rmse / n}, {"psnr_black_floor", black / n}};
  std::vector<Metric> metrics{{"psnr_all_views", all / n}, {"density_rmse", rmse / n}, {"psnr_black_floor", black / n}};
  if (coarse_) {
    for (const int side : {0, 1}) {
      const std::string suffix = side == 1 ? "_mirrored" : "";
      metrics.push_back({"psnr_novel_inference" + suffix, inferenceFine[side] / n});
      metrics.push_back({"psnr_novel_coarse" + suffix, inferenceCoarse[side] / n});
      metrics.push_back({"psnr_gain_inference" + suffix, (inferenceFine[side] - inferenceCoarse[side]) / n});
    }
  }
  return metrics;
}

std::string GrhoTrainer::dataSummary() const { return describeData(data_); }

double GrhoTrainer::forwardFlops() {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  const Var images = variable(Tensor(context_, {kSlots, 1, generator_.views().height, generator_.views().width}));
  stream.fillZero(images->value);
  modules::FlopCounter counter;
  generator_.forward(tape, images, presence_);
  return counter.flops();
}

}  // namespace smokesvd::train
