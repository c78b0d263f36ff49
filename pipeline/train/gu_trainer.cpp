#include "pipeline/train/gu_trainer.h"

#include <cmath>

#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/models/model_json.h"
#include "nets/modules/flop_counter.h"
#include "pipeline/differentiable/physics.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/train/view_losses.h"
#include "runtime/error.h"

namespace smokesvd::train {

GuTrainer::GuTrainer(Context& context, const networks::NetworkConfig& config, const dataset::SceneDataset& data,
                     const std::filesystem::path& models)
    : context_(context), config_(config), data_(data),
      generator_(context, models::unet3PlusFromJson(config.model, config.source + " [model]"), data.preset()),
      look_(context) {
  const std::string lossWhere = config.source + " [loss]", optionsWhere = config.source + " [options]";
  models::requireKnownKeys(config.loss, {"velocity", "divergence", "advected_density", "advected_render", "deep_supervision"},
                           lossWhere);
  models::requireKnownKeys(config.options, {"finetune_steps", "finetune_on", "render_views"}, optionsWhere);
  weights_ = {networks::number(config.loss, "velocity", lossWhere), networks::number(config.loss, "divergence", lossWhere),
              networks::number(config.loss, "deep_supervision", lossWhere),
              networks::number(config.loss, "advected_density", lossWhere),
              networks::number(config.loss, "advected_render", lossWhere)};
  finetuneSteps_ = networks::integer(config.options, "finetune_steps", optionsWhere);
  if (finetuneSteps_ < 0 || finetuneSteps_ > config.train.steps)
    throw Error(optionsWhere + ": 'finetune_steps' must be in [0, steps]");
  const int views = static_cast<int>(networks::integer(config.options, "render_views", optionsWhere));
  if (views < 1 || views > 16) throw Error(optionsWhere + ": 'render_views' must be in [1, 16]");
  const Preset& p = data.preset();
  lossViews_ = render::uploadViews(context, orbitCameras(orbitAngles(views), networks::presetGrid(p), p.imageWidth, p.imageHeight));
  if (finetuneSteps_ > 0) {
    if (networks::text(config.options, "finetune_on", optionsWhere) != "grho-fine")
      throw Error(optionsWhere + ": 'finetune_on' must be \"grho-fine\"");
    grho_ = networks::loadFrozenDensityGenerator(context, models, networks::Network::GrhoFine, p);
  }
  for (const dataset::SceneEntry& s : data.training())
    if (s.scene.stepsPerFrame != 1 || s.scene.dt != 1.0 || s.scene.advection != data.training()[0].scene.advection)
      throw Error(s.directory.string() + ": G_u trains on scenes of one step of dt 1 per frame, all with one advection scheme");
  advection_.scheme = data.training()[0].scene.advection;
  advection_.strength = static_cast<float>(data.training()[0].scene.advectionStrength);
  current_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  next_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  inflow_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  flags_ = variable(Tensor(context, {p.grid.z, p.grid.y, p.grid.x}));
  velocity_ = variable(Tensor(context, {3, p.grid.z, p.grid.y, p.grid.x}));
  generator_.net().initialize(0x6775);
}

int GuTrainer::upload(const dataset::SceneEntry& scene, int frame, const Augmentation& a) {
  current_->value.upload(augmentedDensity(data_, scene, frame, a));
  next_->value.upload(augmentedDensity(data_, scene, frame + 1, a));
  inflow_->value.upload(augmentedInflow(data_, scene, frame + 1, a));
  velocity_->value.upload(augmentedVelocity(data_, scene, frame, a));
  flags_->value.upload(augmentedFlags(data_, scene, a));
  return look_.upload(augmentedLook(data_, scene, a));
}

int GuTrainer::prepare(int64_t step, diffusion::Gaussian& random) {
  const FrameDraw draw = drawFrames(data_.training(), 2, 0, random);
  const Augmentation a = drawAugmentation(config_.data, random);
  const bool fromGrho = step >= config_.train.steps - finetuneSteps_;
  return upload(*draw.scene, draw.frame, a) + (fromGrho ? 2 : 0);
}

std::pair<Var, Var> GuTrainer::inputs(Tape& tape, bool fromGrho, const render::RenderSettings& settings) {
  if (!fromGrho) return {current_, next_};
  NoGrad noGrad(tape);
  const Var presence = variable(Tensor::fromHost(context_, {networks::kSlots}, std::vector<float>(networks::kSlots, 1.0f)));
  auto reconstructed = [&](const Var& truth) {
    return grho_->forward(tape, diff::render(tape, truth, grho_->views(), settings), presence).density;
  };
  return {reconstructed(current_), reconstructed(next_)};
}

LossTerms GuTrainer::record(Tape& tape, int variant) {
  const render::RenderSettings settings = look_.settings(variant % 2 == 1);
  grids_.push_back(std::make_unique<physics::FlagGrid>(tape.stream(), flags_->value));
  const physics::FlagGrid& grid = *grids_.back();
  const auto [current, next] = inputs(tape, variant >= 2, settings);
  Var truthVelocity, truthDivergence, truthNextRender;
  {
    NoGrad noGrad(tape);
    truthVelocity = diff::macToCentred(tape, velocity_);
    truthDivergence = diff::divergence(tape, truthVelocity, physics::Staggering::Centred);
    truthNextRender = diff::render(tape, next_, lossViews_, settings);
  }
  const networks::VelocityOutput out = generator_.forward(tape, current, next, weights_.deepSupervision > 0);
  const Var advected = diff::advect(tape, grid, current, diff::centredToMac(tape, out.velocity), inflow_, advection_);

  LossTerms terms;
  auto weighted = [&](const char* name, double weight, const Var& loss) {
    terms.terms.emplace_back(name, fn::scale(tape, loss, static_cast<float>(weight)));
  };
  weighted("velocity", weights_.velocity, fn::mseLoss(tape, out.velocity, truthVelocity));
  weighted("divergence", weights_.divergence,
           fn::mseLoss(tape, diff::divergence(tape, out.velocity, physics::Staggering::Centred), truthDivergence));
  weighted("advected_density", weights_.advectedDensity, fn::mseLoss(tape, advected, next_));
  weighted("advected_render", weights_.advectedRender,
           fn::mseLoss(tape, diff::render(tape, advected, lossViews_, settings), truthNextRender));
  if (!out.supervision.empty()) {
    std::vector<Var> heads;
    for (const Var& head : out.supervision) heads.push_back(fn::mseLoss(tape, head, truthVelocity));
    weighted("deep_supervision", weights_.deepSupervision / static_cast<double>(heads.size()), sumOf(tape, heads));
  }
  addUpTotal(tape, terms);
  return terms;
}

std::vector<Metric> GuTrainer::validate() {
  const int samples = config_.train.validationSamples;
  double velocityError = 0, ratio = 0, truthRatio = 0, advectedError = 0, stillError = 0;
  for (int k = 0; k < samples; ++k) {
    const FrameDraw draw = validationFrames(data_.validation(), k, samples, 2, 0);
    upload(*draw.scene, draw.frame, Augmentation{});
    Stream stream(context_);
    Tape tape(stream);
    NoGrad noGrad(tape);
    const physics::FlagGrid grid(stream, flags_->value);
    const Var truth = diff::macToCentred(tape, velocity_);
    const Var velocity = generator_.forward(tape, current_, next_).velocity;
    const Var advected = diff::advect(tape, grid, current_, diff::centredToMac(tape, velocity), inflow_, advection_);
    const Var advectedByTruth = diff::advect(tape, grid, current_, velocity_, inflow_, advection_);
    stream.submit();
    const std::vector<float> u = velocity->value.download(), us = truth->value.download();
    const std::vector<float> a = advected->value.download(), n = next_->value.download(), c = current_->value.download(),
                             in = inflow_->value.download(), at = advectedByTruth->value.download();
    double du = 0, da = 0, ds = 0, dt = 0;
    for (std::size_t i = 0; i < u.size(); ++i) du += (static_cast<double>(u[i]) - us[i]) * (static_cast<double>(u[i]) - us[i]);
    for (std::size_t i = 0; i < a.size(); ++i) {
      da += (static_cast<double>(a[i]) - n[i]) * (static_cast<double>(a[i]) - n[i]);
      dt += (static_cast<double>(at[i]) - n[i]) * (static_cast<double>(at[i]) - n[i]);
      const double still = static_cast<double>(c[i]) + in[i] - n[i];
      ds += still * still;
    }
    velocityError += std::sqrt(du / static_cast<double>(u.size()));
    advectedError += std::sqrt(da / static_cast<double>(a.size()));
    stillError += std::sqrt(ds / static_cast<double>(a.size()));
    ratio += ds > 0 ? std::sqrt(da / ds) : 0.0;
    truthRatio += ds > 0 ? std::sqrt(dt / ds) : 0.0;
  }
  const double n = samples;
  return {{"advection_error_ratio", ratio / n}, {"advection_error_ratio_true_velocity", truthRatio / n},
          {"velocity_rmse", velocityError / n},
          {"advected_density_rmse", advectedError / n}, {"no_motion_density_rmse", stillError / n}};
}

std::string GuTrainer::dataSummary() const {
  return describeData(data_) + (grho_ ? "; the last " + std::to_string(finetuneSteps_) + " steps on fine G_rho densities" : "");
}

double GuTrainer::forwardFlops() {
  Stream stream(context_);
  Tape tape(stream);
  NoGrad noGrad(tape);
  modules::FlopCounter counter;
  generator_.forward(tape, current_, next_);
  return counter.flops();
}

}  // namespace smokesvd::train
