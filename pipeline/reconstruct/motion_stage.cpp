#include "pipeline/reconstruct/motion_stage.h"

#include <cmath>

#include "nets/functional/activation.h"
#include "nets/functional/elementwise.h"
#include "nets/functional/losses.h"
#include "nets/optim/adam.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/differentiable/physics.h"
#include "pipeline/differentiable/render.h"
#include "pipeline/reconstruct/inflow_mask.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {

MotionResult advanceDensity(Context& context, MethodModels& models, const FrameState& state, int frame,
                            const physics::FlagGrid& grid, const Tensor& target, const Tensor& input,
                            const render::ViewSet& inputView, const render::RenderSettings& look, const physics::AdvectionParams& advection,
                            const MotionOptions& options) {
  MotionResult result;
  const Preset& preset = models.coarse->preset();
  if (frame == 0) {
    result.density = target;
    result.inflow = target;
    return result;
  }
  if (options.inflowIterations < 0) throw Error("--inflow-iterations must be >= 0");
  Tensor advected;
  {
    Stream stream(context);
    Tape tape(stream);
    NoGrad noGrad(tape);
    const Var u = models.velocity->forward(tape, variable(state.density), variable(target)).velocity;
    const Var mac = diff::centredToMac(tape, u);
    advected = diff::advect(tape, grid, variable(state.density), mac, nullptr, advection)->value;
    result.velocity = mac->value;
    stream.submit();
  }

  const Tensor mask = Tensor::fromHost(context, preset.grid.volume(), inflowMask(preset.grid, options.inflowHeight));
  const Var inflow = variable(Tensor(context, preset.grid.volume()), true, "inflow");
  // Frame 0's "inflow" is its whole density (the simulator's convention for the first frame), not a rate of
  // inflow: frame 1 starts from none and is held to none, or it would add the first plume again each frame.
  const Var previous = variable(frame == 1 ? Tensor(context, preset.grid.volume()) : state.inflow);
  {
    Stream copy(context);
    if (frame == 1) copy.fillZero(previous->value);
    copy.copy(previous->value, inflow->value);
    copy.submit();
  }
  if (options.inflowIterations > 0) {
    const NamedParameters parameters{{"inflow", inflow}};
    optim::Adam adam(context, parameters,
                     optim::AdamOptions::adamW(optim::LrSchedule::cosine(options.inflowLr, options.inflowIterations,
                                                                         options.inflowLr * 0.1),
                                               0.0));
    optim::GradClip clip(context, 1.0);
    Stream stream(context);
    Tape tape(stream);
    const Var masked = fn::mul(tape, inflow, variable(mask));
    const Var estimate = fn::add(tape, variable(advected), masked);
    const Var loss = fn::add(
        tape, fn::add(tape, fn::mseLoss(tape, estimate, variable(target)),
                      fn::scale(tape, fn::mseLoss(tape, diff::render(tape, estimate, inputView, look), variable(input.reshaped({1, 1, preset.imageHeight, preset.imageWidth}))),
                                static_cast<float>(options.imageWeight))),
        fn::scale(tape, fn::mseLoss(tape, masked, previous), static_cast<float>(options.smoothWeight)));
    tape.backward(loss);
    clip.record(stream, parameters);
    adam.step(stream, &clip);
    for (int i = 0; i < options.inflowIterations; ++i) stream.submit();
  }
  Stream stream(context);
  Tape tape(stream);
  NoGrad noGrad(tape);
  result.inflow = fn::relu(tape, fn::mul(tape, inflow, variable(mask)))->value;
  result.density = diff::advect(tape, grid, variable(state.density), variable(result.velocity), variable(result.inflow), advection)->value;
  stream.submit();
  return result;
}

}  // namespace smokesvd::reconstruct
