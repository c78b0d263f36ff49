#include "pipeline/train/training_step.h"

namespace smokesvd::train {

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
