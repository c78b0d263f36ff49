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

using networks::kSlots;

GrhoTrainer::GrhoTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data)
    : context_(context), config_(config), data_(data),
      generator_(context, models::unet3PlusFromJson(config.model, config.source + " [model]"), data.preset()),
      look_(context) {
  const std::string lossWhere = config.source + " [loss]", optionsWhere = config.source + " [options]";
  models::requireKnownKeys(config.loss, {"density", "render_input", "render_unseen", "deep_supervision"}, lossWhere);
  models::requireKnownKeys(config.options, {"views", "extra_view_probability"}, optionsWhere);
  weights_ = {networks::number(config.loss, "density", lossWhere), networks::number(config.loss, "render_input", lossWhere),
              networks::number(config.loss, "render_unseen", lossWhere), networks::number(config.loss, "deep_supervision", lossWhere)};
  const std::string views = networks::text(config.options, "views", optionsWhere);
  if (views != "fine" && views != "coarse") throw Error(optionsWhere + ": 'views' must be \"fine\" or \"coarse\"");
  fine_ = views == "fine";
  extraViewProbability_ = networks::number(config.options, "extra_view_probability", optionsWhere);
  const Preset& p = data.preset();
  density_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  presence_ = variable(Tensor(context, {kSlots}));
  sqrtInputWeights_ = variable(Tensor(context, {kSlots}));
  sqrtUnseenWeights_ = variable(Tensor(context, {kSlots}));
  generator_.net().initialize(0x67726f);
}

int GrhoTrainer::upload(const std::vector<float>& density, const render::RenderSettings& look,
                        const std::vector<bool>& inputs) {
  density_->value.upload(density);
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
  return look_.upload(look);
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
  return upload(augmentedDensity(data_, *draw.scene, draw.frame, a), augmentedLook(data_, *draw.scene, a), inputs);
}

LossTerms GrhoTrainer::record(Tape& tape, int variant) {
  const render::RenderSettings settings = look_.settings(variant == 1);
  Var truth;
  {
    NoGrad noGrad(tape);
    truth = diff::render(tape, density_, generator_.views(), settings);
  }
  const Var input = fn::mulSample(tape, truth, presence_);
  const networks::DensityOutput out = generator_.forward(tape, input, presence_, weights_.deepSupervision > 0);
  const Var renders = diff::render(tape, out.density, generator_.views(), settings);

  LossTerms terms;
  terms.terms.emplace_back("density", fn::scale(tape, fn::mseLoss(tape, out.density, density_), static_cast<float>(weights_.density)));
  terms.terms.emplace_back("render_input", weightedViewMse(tape, renders, truth, sqrtInputWeights_));
  terms.terms.emplace_back("render_unseen", weightedViewMse(tape, renders, truth, sqrtUnseenWeights_));
  if (!out.supervision.empty()) {
    Var sum;
    for (const Var& head : out.supervision) {
      const Var l = fn::mseLoss(tape, head, density_);
      sum = sum ? fn::add(tape, sum, l) : l;
    }
    terms.terms.emplace_back(
        "deep_supervision", fn::scale(tape, sum, static_cast<float>(weights_.deepSupervision / static_cast<double>(out.supervision.size()))));
  }
  Var total;
  for (const auto& [name, term] : terms.terms) total = total ? fn::add(tape, total, term) : term;
  terms.total = total;
  return terms;
}

GrhoTrainer::ViewErrors GrhoTrainer::evaluate(int variant) {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  const render::RenderSettings settings = look_.settings(variant == 1);
  const Var truth = diff::render(tape, density_, generator_.views(), settings);
  const Var density = generator_.forward(tape, fn::mulSample(tape, truth, presence_), presence_).density;
  const Var renders = diff::render(tape, density, generator_.views(), settings);
  stream.submit();
  const std::vector<float> t = truth->value.download(), r = renders->value.download();
  const std::vector<float> d = density->value.download(), dt = density_->value.download();
  ViewErrors e;
  const std::size_t pixels = t.size() / kSlots;
  const std::vector<float> black(pixels, 0.0f);
  for (int v = 0; v < kSlots; ++v) {
    const std::span<const float> tv(t.data() + v * pixels, pixels), rv(r.data() + v * pixels, pixels);
    e.psnr.push_back(psnr(rv, tv));
    e.blackPsnr.push_back(psnr(black, tv));
  }
  double sum = 0;
  for (std::size_t i = 0; i < d.size(); ++i) sum += (static_cast<double>(d[i]) - dt[i]) * (static_cast<double>(d[i]) - dt[i]);
  e.densityRmse = std::sqrt(sum / static_cast<double>(d.size()));
  return e;
}

std::vector<Metric> GrhoTrainer::validate() {
  const int samples = config_.train.validationSamples;
  double all = 0, novel = 0, frontOnly = 0, black = 0, rmse = 0;
  for (int k = 0; k < samples; ++k) {
    const FrameDraw draw = validationFrames(data_.validation(), k, samples, 1, 0);
    const std::vector<float> density = data_.density(*draw.scene, draw.frame);
    const render::RenderSettings look = data_.look(*draw.scene);
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
    if (fine_) {
      const ViewErrors e = evaluate(upload(density, look, std::vector<bool>(kSlots, true)));
      all += mean(e.psnr, false);
      black += mean(e.blackPsnr, false);
      rmse += e.densityRmse;
    } else {
      std::vector<bool> inputs(kSlots, false);
      inputs[networks::kFrontSlot] = inputs[networks::kSideSlot] = true;
      const ViewErrors e = evaluate(upload(density, look, inputs));
      novel += mean(e.psnr, true);
      black += mean(e.blackPsnr, true);
      rmse += e.densityRmse;
      inputs[networks::kSideSlot] = false;
      frontOnly += mean(evaluate(upload(density, look, inputs)).psnr, true);
    }
  }
  const double n = samples;
  if (fine_)
    return {{"psnr_all_views", all / n}, {"density_rmse", rmse / n}, {"psnr_black_floor", black / n}};
  return {{"psnr_novel_front_side", novel / n}, {"psnr_novel_front_only", frontOnly / n},
          {"density_rmse", rmse / n}, {"psnr_black_floor", black / n}};
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
