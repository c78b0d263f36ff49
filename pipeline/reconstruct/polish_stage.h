// Stage 7, beyond the paper: `--polish N` refines each frame's motion by N AdamW steps through the
// differentiable advection and renderer, so that the input view is matched closely while the other
// views stay close to the network's refined views, and the output keeps the simulator's relation:
//   rho^_t = A(rho^_t-1, u) + relu(m q)                  (frame 0: rho^_0 = relu(q))
//   L = l_in ||R_in(rho^_t) - w_in||^2 + l_views mean_{a != 0} ||R(rho^_t, a) - w_f(a)||^2
//     + l_div mean (div u)^2 + l_prior ||u - u_G||^2
// over the MAC velocity u (from G_u's u_G) and the inflow q (from the inflow stage), m the inflow mask, w_in the
// input as its camera saw it and R_in the render through that camera (motion_stage.h).
// Off by default (N = 0); docs/reconstruction.md reports what it buys and costs.
#pragma once

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "pipeline/reconstruct/frame_state.h"
#include "pipeline/reconstruct/motion_stage.h"
#include "pipeline/render/renderer.h"
#include "pipeline/render/view_set.h"

namespace smokesvd::reconstruct {

struct PolishOptions {
  int steps = 0;
  double lr = 0.02;
  double inputWeight = 1.0, viewWeight = 0.25, divergenceWeight = 1.0, priorWeight = 1.0;
};

// Refines `motion` (velocity, inflow, density) of `frame` in place; `views` [16, 1, h, w] are the
// frame's view-slot images (input, side, refined), `input` [1, 1, h, w] the input as its camera saw it, and
// `slotViews` the cameras: the input's camera at slot 0, the orbit slots at the others.
void polishMotion(Context& context, const FrameState& state, int frame, const physics::FlagGrid& grid,
                  const render::ViewSet& slotViews, const Tensor& views, const Tensor& input,
                  const render::RenderSettings& look,
                  const physics::AdvectionParams& advection, const MotionOptions& motionOptions,
                  const PolishOptions& options, MotionResult& motion);

}  // namespace smokesvd::reconstruct
