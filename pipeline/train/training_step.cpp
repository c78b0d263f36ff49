#include "pipeline/train/training_step.h"

#include <algorithm>

#include "nets/optim/schedule.h"

namespace smokesvd::train {

optim::AdamOptions adamWOptions(const networks::TrainSettings& t) {
  const optim::LrSchedule schedule =
      optim::LrSchedule::cosine(t.lr, std::max<int64_t>(1, t.steps - t.warmup), t.lr * t.minLrFraction, t.warmup);
  return optim::AdamOptions::adamW(schedule, t.weightDecay);
}

LossTerms recordTrainingStep(Tape& tape, StageTrainer& trainer, int variant, const NamedParameters& parameters,
                             const StepOptimizer& optimizer) {
  clearGradients(parameters);
  LossTerms terms = trainer.record(tape, variant);
  tape.backward(terms.total);
  optimizer.clip.record(tape.stream(), parameters);
  optimizer.adam.step(tape.stream(), &optimizer.clip);
  optimizer.ema.update(tape.stream());
  return terms;
}

}  // namespace smokesvd::train
