#include "pipeline/reconstruct/polish_stage.h"

#include <algorithm>
#include <cmath>

#include "nets/functional/activation.h"
#include "nets/functional/broadcast.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/functional/reduce_axes.h"
#include "nets/optim/adam.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/differentiable/physics.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/reconstruct/inflow_mask.h"
#include "pipeline/train/view_losses.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace {

// The view-slot targets with slot 0 replaced by the input as its camera saw it.
Tensor targetsWithInput(Context& context, const Tensor& views, const Tensor& input) {
  std::vector<float> values = views.download();
  const std::vector<float> front = input.download();
  std::copy(front.begin(), front.end(), values.begin() + static_cast<std::ptrdiff_t>(networks::kFrontSlot * front.size()));
  return Tensor::fromHost(context, views.shape(), values);
}

}  // namespace

void polishMotion(Context& context, const FrameState& state, int frame, const physics::FlagGrid& grid,
                  const render::ViewSet& slotViews, const Tensor& views, const Tensor& input,
                  const render::RenderSettings& look,
                  const physics::AdvectionParams& advection, const MotionOptions& motionOptions,
                  const PolishOptions& options, MotionResult& motion) {
  if (options.steps <= 0) return;
  const GridSize& g = grid.size();
  const Tensor mask = Tensor::fromHost(context, g.volume(), inflowMask(g, motionOptions.inflowHeight));
  auto copyOf = [&](const Tensor& t, const std::string& name) {
    const Var v = variable(Tensor(context, t.shape()), true, name);
    Stream s(context);
    s.copy(t, v->value);
    s.submit();
    return v;
  };
  const Var inflow = copyOf(motion.inflow, "inflow");
  const Var velocity = frame > 0 ? copyOf(motion.velocity, "velocity") : nullptr;
  NamedParameters parameters{{"inflow", inflow}};
  if (velocity) parameters.emplace_back("velocity", velocity);
  std::vector<float> weights(networks::kSlots, static_cast<float>(std::sqrt(options.viewWeight / (networks::kSlots - 1))));
  weights[networks::kFrontSlot] = static_cast<float>(std::sqrt(options.inputWeight));
  const Var sqrtWeights = variable(Tensor::fromHost(context, {networks::kSlots}, weights));

  optim::Adam adam(context, parameters,
                   optim::AdamOptions::adamW(optim::LrSchedule::cosine(options.lr, options.steps, options.lr * 0.1), 0.0));
  optim::GradClip clip(context, 1.0);
  Stream stream(context);
  Tape tape(stream);
  auto density = [&](Tape& t) {
    if (!velocity) return fn::relu(t, inflow);
    const Var in = fn::relu(t, fn::mul(t, inflow, variable(mask)));
    return diff::advect(t, grid, variable(state.density), velocity, in, advection);
  };
  const Var rho = density(tape);
  Var loss = train::weightedViewMse(tape, diff::render(tape, rho, slotViews, look),
                                       variable(targetsWithInput(context, views, input)), sqrtWeights);
  if (velocity) {
    const Var divergence = diff::divergence(tape, velocity, physics::Staggering::Mac);
    loss = fn::add(tape, loss,
                   fn::scale(tape, fn::reshape(tape, fn::mean(tape, fn::mul(tape, divergence, divergence)), {1}),
                             static_cast<float>(options.divergenceWeight)));
    loss = fn::add(tape, loss,
                   fn::scale(tape, fn::mseLoss(tape, velocity, variable(motion.velocity)), static_cast<float>(options.priorWeight)));
  }
  tape.backward(loss);
  clip.record(stream, parameters);
  adam.step(stream, &clip);
  for (int i = 0; i < options.steps; ++i) stream.submit();

  Stream finish(context);
  Tape out(finish);
  NoGrad noGrad(out);
  if (velocity) {
    motion.inflow = fn::relu(out, fn::mul(out, inflow, variable(mask)))->value;
    motion.velocity = velocity->value;
    motion.density = diff::advect(out, grid, variable(state.density), velocity, variable(motion.inflow), advection)->value;
  } else {
    motion.inflow = fn::relu(out, inflow)->value;
    motion.density = motion.inflow;
  }
  finish.submit();
}

}  // namespace smokesvd::reconstruct
