// Stages 2 and 3, the density of frame t (Algorithm 2): the coarse G_rho from the front view and the
// side view; then, group by group (near, mid, far views), the renders of the current coarse density at
// the group's slots and at +-beta are refined by NvRef (with the refined images of those slots at t-1
// and t-2; at frames 0 and 1, which have none, the render itself stands in, as in training), and the
// coarse G_rho runs again on every view known so far; finally the fine G_rho on all 16. Ablations:
// `refine = false` keeps the first coarse density; `progressive = false` refines all 14 novel views from
// the first coarse density in one pass before the fine G_rho.
#pragma once

#include "pipeline/reconstruct/frame_state.h"
#include "pipeline/reconstruct/method_models.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::reconstruct {

struct DensityOptions {
  bool refine = true;
  bool progressive = true;
};

struct DensityResult {
  Tensor density;     // [D, H, W]: the fine G_rho's (or the coarse one's without refinement)
  Tensor sideRender;  // [1, 1, h, w]: the 90-degree render of the first coarse density (SvDiff's condition)
  Tensor views;       // [16, 1, h, w]: the front view, the side view and the 14 refined (or rendered) views
};

DensityResult reconstructDensity(Context& context, MethodModels& models, const FrameState& state, int frame,
                                 const Tensor& front, const Tensor& side, const render::RenderSettings& look,
                                 const DensityOptions& options);

}  // namespace smokesvd::reconstruct
