// What the training loop (training_run.h) needs of a network's trainer. A trainer owns its network and
// records one training step (forward and weighted losses) onto a tape; the loop records that step once
// per variant, adds the backward pass, clipping, AdamW and the EMA, and submits it again for every
// step after the trainer has uploaded that step's sample into the tensors the recording reads.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "nets/autograd/tape.h"
#include "nets/diffusion/gaussian.h"
#include "nets/modules/module.h"

namespace smokesvd::train {

struct LossTerms {
  std::vector<std::pair<std::string, Var>> terms;  // each weighted term, a [1] tensor
  Var total;                                       // their sum, what the step minimises
};

// The sum of `values` (at least one), added left to right.
Var sumOf(Tape& tape, const std::vector<Var>& values);
// Sets terms.total to the sum of terms.terms, in their order.
void addUpTotal(Tape& tape, LossTerms& terms);

struct Metric {
  std::string name;
  double value = 0;
};

// The random numbers of one step: a generator seeded by (run seed, step), so a resumed run draws
// exactly what an uninterrupted one drew.
diffusion::Gaussian stepRandom(uint64_t seed, int64_t step);

class StageTrainer {
 public:
  virtual ~StageTrainer() = default;
  virtual modules::Module& model() = 0;
  // Names of the distinct recordings the trainer needs (e.g. a lit and an unlit render, a guided and an
  // unguided diffusion step); each is recorded the first time prepare() asks for it.
  virtual std::vector<std::string> variants() const { return {"step"}; }
  // Draws the sample of `step`, uploads it, and returns the variant (index into variants()) to submit.
  virtual int prepare(int64_t step, diffusion::Gaussian& random) = 0;
  // Records variant `variant` of the step: forward and losses, reading the tensors prepare() fills.
  virtual LossTerms record(Tape& tape, int variant) = 0;
  // Metrics of the model's current weights (the loop puts the EMA in place) on held-out scenes; the
  // first is the one progress reports.
  virtual std::vector<Metric> validate() = 0;
  // A line for the model card about the data, e.g. "108 training scenes of /data (seeds 1000-1119)".
  virtual std::string dataSummary() const = 0;
  // FLOPs of one forward pass of the network (modules::FlopCounter), for the model card and the progress line.
  virtual double forwardFlops() = 0;
};

}  // namespace smokesvd::train
