// Stages 4 to 6, the motion from frame t-1 to t (supplement C.5, C.6): the velocity
//   u_t-1 = G_u(rho^_t-1, rho_t)                     rho^ the output (advected) density, rho_t the fine G_rho's
// and the inflow of frame t, optimised by AdamW on the paper's L_s, warm-started from the previous inflow:
//   L_s = ||rho_t - (a + m in)||^2 + l_img ||w_in - R_in(a + m in)||^2 + l_s ||m in - in_t-1||^2,
//   a = A(rho^_t-1, u_t-1)                           MacCormack, the simulator's boundaries
// w_in is the input as its camera saw it and R_in the render through that camera (the calibrated perspective
// camera over the crop for calibrated footage, else the front view, slot 0);
// m zeroes the inflow above a height (a fraction of the box) and on the outer cell layer; the result is
// clamped to be non-negative. The output density is then exactly what the simulator's relation gives:
//   rho^_t = A(rho^_t-1, u_t-1) + in_t
// so that density[t] = A(density[t-1], velocity[t-1]) + inflow[t] holds for the written files. Frame 0
// has no motion: its inflow is its whole density; frame 1 therefore starts from, and is held to, no inflow
// (in_0 = 0 in L_s), not to that first plume.
#pragma once

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "pipeline/reconstruct/frame_state.h"
#include "pipeline/reconstruct/method_models.h"
#include "pipeline/render/renderer.h"
#include "pipeline/render/view_set.h"

namespace smokesvd::reconstruct {

struct MotionOptions {
  int inflowIterations = 40;
  double inflowLr = 0.005;
  double inflowHeight = 0.25;  // inflow only in the lowest quarter of the box
  double imageWeight = 1.0;
  double smoothWeight = 1.0;
};

struct MotionResult {
  Tensor velocity;  // [3, D, H, W], MAC: the velocity of frame t-1 (undefined at frame 0)
  Tensor inflow;    // [D, H, W]
  Tensor density;   // [D, H, W]: rho^_t
};

MotionResult advanceDensity(Context& context, MethodModels& models, const FrameState& state, int frame,
                            const physics::FlagGrid& grid, const Tensor& target, const Tensor& input,
                            const render::ViewSet& inputView, const render::RenderSettings& look, const physics::AdvectionParams& advection,
                            const MotionOptions& options);

}  // namespace smokesvd::reconstruct
