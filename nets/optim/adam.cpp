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
  for (const auto& [name, parameter] : parameters_) {
    require(parameter && parameter->value.defined(), "parameter '" + name + "' has no value");
    require(parameter->requiresGrad, "parameter '" + name + "' does not require a gradient");
    values_.push_back(parameter->value);
  }
  layout_ = flatLayout(values_);
  expAvg_ = zeroState(context, layout_, values_);
  expAvgSq_ = zeroState(context, layout_, values_);
  gatheredValues_ = zeroFlat(context, layout_);
  gatheredGradients_ = zeroFlat(context, layout_);
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

  std::vector<Tensor> gradients;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const Variable& parameter = *parameters_[i].second;
    if (parameter.grad.defined())
      ops::requireSameShape(("Adam, parameter '" + parameters_[i].first + "' and its gradient").c_str(),
                            {&parameter.value, &parameter.grad});
    gradients.push_back(parameter.grad);
  }
  auto hasGradient = [&](std::size_t i) { return gradients[i].defined(); };
  const FlatParts values = flatParts(layout_, values_, hasGradient);
  const FlatParts gathered = flatParts(layout_, gradients, hasGradient);
  stream.gather(values.tensors, values.offsets, gatheredValues_);
  stream.gather(gathered.tensors, gathered.offsets, gatheredGradients_);

  const Kernel& update = stream.kernel("nn/adam", kWorkgroup, {kVec4sPerInvocation});
  const Tensor& factor = clip ? clip->result() : noClip_;
  // Updates elements [first, end) of p and g, with moments m and v (first a multiple of 4).
  auto record = [&](const Tensor& p, const Tensor& g, const Tensor& m, const Tensor& v, int64_t first, int64_t end) {
    struct { uint32_t firstVec4, end; float oneMinusBeta1, beta2, oneMinusBeta2, eps, l2Decay; } push{
        static_cast<uint32_t>(first / 4),
        static_cast<uint32_t>(end),
        static_cast<float>(1 - options_.beta1),
        static_cast<float>(options_.beta2),
        static_cast<float>(1 - options_.beta2),
        static_cast<float>(options_.eps),
        options_.decoupledWeightDecay ? 0.0f : static_cast<float>(options_.weightDecay)};
    const int64_t vec4s = (end + 3) / 4 - first / 4;
    stream.dispatchFlat(update, {asVec4(scalars_), factor, asVec4(p), asVec4(g), asVec4(m), asVec4(v), p, m, v}, push,
                        (vec4s + kVec4sPerInvocation - 1) / kVec4sPerInvocation);
  };
  // The gathered parameters with a gradient, in runs of neighbours in the flat tensors.
  int64_t runFirst = -1, runEnd = -1;
  for (std::size_t i = 0; i < values_.size(); ++i) {
    if (!layout_.gathered(i)) continue;
    if (!hasGradient(i)) {
      if (runFirst >= 0) record(gatheredValues_, gatheredGradients_, expAvg_.flat, expAvgSq_.flat, runFirst, runEnd);
      runFirst = -1;
      continue;
    }
    if (runFirst < 0) runFirst = layout_.offsets[i];
    runEnd = layout_.offsets[i] + values_[i].numel();
  }
  if (runFirst >= 0) record(gatheredValues_, gatheredGradients_, expAvg_.flat, expAvgSq_.flat, runFirst, runEnd);
  for (std::size_t i = 0; i < values_.size(); ++i)
    if (!layout_.gathered(i) && hasGradient(i))
      record(values_[i], gradients[i], expAvg_.alone[i], expAvgSq_.alone[i], 0, values_[i].numel());
  stream.scatter(gatheredValues_, values.offsets, values.tensors);
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
  std::vector<std::pair<std::string, Tensor>> like;
  for (const auto& [name, parameter] : parameters_) like.emplace_back(name + ".exp_avg", parameter->value);
  const std::vector<std::pair<std::string, Tensor>> first = copyState(expAvg_, layout_, like);
  for (auto& [name, tensor] : like) name += "_sq";
  const std::vector<std::pair<std::string, Tensor>> second = copyState(expAvgSq_, layout_, like);
  std::vector<std::pair<std::string, Tensor>> state;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    state.push_back(first[i]);
    state.push_back(second[i]);
  }
  return state;
}

void Adam::restoreState(const std::vector<std::pair<std::string, Tensor>>& state) {
  require(state.size() == 2 * parameters_.size(),
          "restoring " + std::to_string(state.size()) + " state tensors, expected " + std::to_string(2 * parameters_.size()));
  std::vector<Tensor> first, second;
  for (std::size_t i = 0; i < parameters_.size(); ++i) {
    const std::string& name = parameters_[i].first;
    const Tensor& m = state[2 * i].second;
    const Tensor& v = state[2 * i + 1].second;
    require(state[2 * i].first == name + ".exp_avg" && state[2 * i + 1].first == name + ".exp_avg_sq",
            "restoring state: expected '" + name + ".exp_avg' and '.exp_avg_sq' at " + std::to_string(2 * i) +
                ", got '" + state[2 * i].first + "' and '" + state[2 * i + 1].first + "'");
    ops::requireSameShape(("Adam, the restored state of '" + name + "'").c_str(), {&values_[i], &m, &v});
    first.push_back(m);
    second.push_back(v);
  }
  optim::restoreState(first, expAvg_, layout_);
  optim::restoreState(second, expAvgSq_, layout_);
}

}  // namespace smokesvd::optim
