// One training step as every run records it, shared by the training loop (training_run.h) and the
// training-step benchmarks (tools/bench): the trainer's forward and weighted losses for one variant,
// the backward pass, the global-norm clip, AdamW and the EMA update, all onto the tape's stream.
#pragma once

#include "nets/optim/adam.h"
#include "nets/optim/ema.h"
#include "nets/optim/grad_clip.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"

namespace smokesvd::train {

// The optimiser state one recording updates: AdamW with its schedule, the clip it divides by, the EMA.
struct StepOptimizer {
  const optim::Adam& adam;
  const optim::GradClip& clip;
  const optim::Ema& ema;
};

// AdamW as a config's training settings ask: a cosine schedule from `lr` to `lr * minLrFraction` over the
// steps after a linear warm-up, and the decoupled weight decay.
optim::AdamOptions adamWOptions(const networks::TrainSettings& settings);

// Clears the gradients of `parameters` (a recording computes its own), records variant `variant` of the
// trainer's step onto `tape` and the update after it; returns the loss terms the recording writes.
LossTerms recordTrainingStep(Tape& tape, StageTrainer& trainer, int variant, const NamedParameters& parameters,
                             const StepOptimizer& optimizer);

}  // namespace smokesvd::train
