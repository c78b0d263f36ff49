#include "nets/optim/adam.h"

#include <cmath>


#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::optim {
namespace {

// 256 lanes, two vec4s each: about 15 % faster than one vec4 per lane at 128 on lavapipe (interleaved
// runs of tools/bench/optim_benchmarks.cpp's kernel on a busy machine).
constexpr std::array<uint32_t, 3> kWorkgroup{256, 1, 1};
constexpr int32_t kVec4sPerInvocation = 2;
constexpr int64_t kScalarCount = 8;

void require(bool ok, const std::string& what) {
  if (!ok) throw Error("Adam: " + what);
}

}  // namespace

AdamOptions AdamOptions::adamW(LrSchedule schedule, double weightDecay) {
  AdamOptions options;
  options.schedule = schedule;
  options.weightDecay = weightDecay;
  options.decoupledWeightDecay = true;
  return options;
}

void AdamOptions::validate() const {
  schedule.validate();
  require(beta1 >= 0 && beta1 < 1, "beta1 must be in [0, 1), got " + std::to_string(beta1));
  require(beta2 >= 0 && beta2 < 1, "beta2 must be in [0, 1), got " + std::to_string(beta2));
  require(eps >= 0, "eps must be >= 0, got " + std::to_string(eps));
  require(weightDecay >= 0, "weightDecay must be >= 0, got " + std::to_string(weightDecay));
}

Adam::Adam(Context& context, NamedParameters parameters, AdamOptions options)
    : options_(options), parameters_(std::move(parameters)), scalars_(context, {kScalarCount}),
      noClip_(Tensor::fromHost(context, {2}, std::vector<float>{0.0f, 1.0f})) {
  options_.validate();
  Stream zero(context);
  for (const auto& [name, parameter] : parameters_) {
    require(parameter && parameter->value.defined(), "parameter '" + name + "' has no value");
    require(parameter->requiresGrad, "parameter '" + name + "' does not require a gradient");
    expAvg_.emplace_back(context, parameter->value.shape());
    expAvgSq_.emplace_back(context, parameter->value.shape());
    zero.fillZero(expAvg_.back());
    zero.fillZero(expAvgSq_.back());
  }
  zero.submit();
  setSteps(0);
}

void Adam::step(Stream& stream, const GradClip* clip) const {
  struct {
    float baseLr, logBeta1, logBeta2, decoupledDecay, warmup, stepSize, gamma, cosineSteps, minLr;
  } stepPush{static_cast<float>(options_.schedule.baseLr),
             static_cast<float>(std::log(options_.beta1)),
             static_cast<float>(std::log(options_.beta2)),
             options_.decoupledWeightDecay ? static_cast<float>(options_.weightDecay) : 0.0f,
             static_cast<float>(options_.schedule.warmupSteps),
             static_cast<float>(options_.schedule.stepSize),
             static_cast<float>(options_.schedule.gamma),
             static_cast<float>(options_.schedule.cosineSteps),
             static_cast<float>(options_.schedule.minLr)};
  const Kernel& advance =
      stream.kernel("nn/optimizer_step", {1, 1, 1}, {static_cast<int32_t>(options_.schedule.kind)});
  stream.dispatch(advance, {scalars_}, stepPush, {1, 1, 1});

  const Kernel& update = stream.kernel("nn/adam", kWorkgroup, {kVec4sPerInvocation});
  const Tensor& factor = clip ? clip->result() : noClip_;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const Variable& parameter = *parameters_[i].second;
    if (!parameter.grad.defined()) continue;
    const Tensor& p = parameter.value;
    const Tensor& m = expAvg_[i];
    const Tensor& v = expAvgSq_[i];
    ops::requireSameShape(("Adam, parameter '" + parameters_[i].first + "' and its gradient").c_str(),
                          {&p, &parameter.grad});
    struct { uint32_t n; float oneMinusBeta1, beta2, oneMinusBeta2, eps, l2Decay; } push{
        static_cast<uint32_t>(p.numel()),
        static_cast<float>(1 - options_.beta1),
        static_cast<float>(options_.beta2),
        static_cast<float>(1 - options_.beta2),
        static_cast<float>(options_.eps),
        options_.decoupledWeightDecay ? 0.0f : static_cast<float>(options_.weightDecay)};
    stream.dispatchFlat(update,
                        {asVec4(scalars_), factor, asVec4(p), asVec4(parameter.grad), asVec4(m), asVec4(v), p, m, v},
                        push, ((p.numel() + 3) / 4 + kVec4sPerInvocation - 1) / kVec4sPerInvocation);
  }
}

int64_t Adam::steps() const { return static_cast<int64_t>(scalars_.download()[0]); }

void Adam::setSteps(int64_t steps) {
  require(steps >= 0 && steps <= kMaxSteps,
          "the step counter must be in [0, 2^24], got " + std::to_string(steps));
  std::vector<float> values(kScalarCount, 0.0f);
  values[0] = static_cast<float>(steps);
  scalars_.upload(values);
}

float Adam::lastLearningRate() const { return scalars_.download()[1]; }

std::vector<std::pair<std::string, Tensor>> Adam::namedState() const {
  std::vector<std::pair<std::string, Tensor>> state;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    state.emplace_back(parameters_[i].first + ".exp_avg", expAvg_[i]);
    state.emplace_back(parameters_[i].first + ".exp_avg_sq", expAvgSq_[i]);
  }
  return state;
}

}  // namespace smokesvd::optim
