// Stage 1, the side view of frame t (paper Sec. 3.2): DDIM sampling of SvDiff conditioned on the front
// view and the two previous frames' synthesised side views and side renders; frames 0 and 1 come
// together from SvDiff-init, conditioned on their two front views (a one-frame clip uses its only frame
// twice). The sample is mapped back to [0, 1] and clamped. `synthesize = false` (the ablation and
// baseline) takes the front view mirrored left to right as the side view instead.
// By default each sample starts from pure noise (-1, the paper's sampler); `start` below T - 1 starts from
// the mirrored front view(s) noised to that step instead (SDEdit; the DDIM steps spread over [0, start]),
// which a model that predicts the noise poorly at high steps needs (docs/reconstruction.md). One DDIM step
// gives the model's clean estimate from pure noise alone. With `samples` K > 1 the side view is the mean of K samples
// (seeds seed + t + k * 2^32, k = 0..K-1): a Monte-Carlo estimate of the posterior mean E[w | condition],
// the image of least expected squared error, blurrier than any one sample. With `initShare` s > 0 the side view
// of frames t >= 2 blends in SvDiff-init's estimate of frame t from its and the next front view alone (no
// history), drawn with frame 0's noise at every frame so that it does not flicker; docs/reconstruction.md.
#pragma once

#include <cstdint>
#include <vector>

#include "pipeline/reconstruct/frame_state.h"
#include "pipeline/reconstruct/method_models.h"

namespace smokesvd::reconstruct {

struct SideViewOptions {
  bool synthesize = true;
  int steps = 20;       // DDIM steps for frames t >= 2
  int initSteps = 50;   // DDIM steps for frames 0 and 1
  double eta = 1.0;
  int start = -1;       // the DDIM start step: -1 pure noise (T - 1), lower from the mirrored front view
  uint64_t seed = 0;    // frame t samples with seed + t
  int samples = 1;      // the side view is the mean of this many samples
  // Frames t >= 2: the side view (and the next frames' history) is (1 - s) SvDiff's sample + s SvDiff-init's
  // estimate of frame t from the front views of t and t + 1 alone (no history, frame 0's noise); 0 the paper,
  // 1 no history.
  double initShare = 0.0;
};

// The side view [1, 1, h, w] of `frame`; `front` and `nextFront` are that frame's and the next one's front
// views (device [1, 1, h, w]; nextFront is read at frame 0, and at every frame from 2 on when initShare > 0).
Tensor sideView(Context& context, MethodModels& models, FrameState& state, int frame, const Tensor& front,
                const Tensor& nextFront, const SideViewOptions& options);

}  // namespace smokesvd::reconstruct
