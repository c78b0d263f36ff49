// The training loop every network shares. The step is recorded once per trainer variant (forward,
// losses, backward, global-norm clipping, AdamW with warm-up and cosine decay, EMA) and resubmitted; per
// step the host only uploads the sample and reads the loss terms back. Every `checkpoint_every` steps
// the model, AdamW's moments and step and the EMA go to checkpoint.safetensors (written to a temporary
// name and renamed), with loss.csv and loss.png; every `validate_every` steps the EMA weights are
// validated on held-out scenes (validation.csv). A run resumed from its checkpoint continues bit for bit
// as if it had not stopped: the random numbers of a step depend only on (seed, step), and the CSV rows
// after the checkpoint are dropped. Asked to stop (TrainingOptions::stop), it writes a checkpoint at its next
// log step and returns. At the end the EMA weights become model.safetensors (PyTorch names
// and layouts) with config.json and model_card.md beside them. Files of a run (docs/models.md):
//   OUT/config.json  checkpoint.safetensors  loss.csv  loss.png  validation.csv  run.json
//   OUT/model.safetensors  model_card.md      (when complete)
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "pipeline/networks/network_config.h"
#include "pipeline/train/trainer.h"
#include "runtime/context.h"

namespace smokesvd::train {

struct TrainingOptions {
  std::filesystem::path out;
  bool resume = false;     // continue the run in `out` from its checkpoint
  bool overwrite = false;  // discard whatever run `out` holds
  uint64_t seed = 0;
  int64_t stopAfter = -1;  // stop after this many steps in this call, as if interrupted (-1: run to the end)
  // Once this becomes true (StopOnSignal: Ctrl-C), the run goes on to its next log step, writes a checkpoint
  // there and returns, so that --resume continues it bit for bit with nothing lost.
  const std::atomic<bool>* stop = nullptr;
  bool quiet = false;      // no progress on stderr
  std::filesystem::path initWeights;  // start from these weights (a model.safetensors of the same architecture, or a checkpoint's EMA)
};

struct TrainingResult {
  int64_t steps = 0;          // steps taken in all, after this call
  int64_t stepsThisCall = 0;
  bool complete = false;
  bool stopped = false;       // ended early at options.stop's request, with a checkpoint at `steps`
  double seconds = 0;         // training time over every call
  std::vector<Metric> validation;  // the last validation
};

TrainingResult runTraining(Context& context, StageTrainer& trainer, const networks::NetworkConfig& config,
                           const TrainingOptions& options);

}  // namespace smokesvd::train
