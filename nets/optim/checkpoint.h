// Resumable training checkpoints: model weights, Adam's moments and step, and optionally the EMA, in one
// .safetensors file (docs/file-formats.md):
//   "<parameter>"                       the model's parameters, under their PyTorch names
//   "optimizer.<parameter>.exp_avg"     Adam's first moment
//   "optimizer.<parameter>.exp_avg_sq"  Adam's second moment
//   "ema.<parameter>"                   the EMA shadow (when the checkpoint has an EMA)
// and metadata "format" = "smokesvd-checkpoint", "format_version" = "1", "optimizer" = "adam" or "adamw",
// "step", "lr", "beta1", "beta2", "eps", "weight_decay" (the last five for information), plus the caller's.
// The model's tensors keep their plain names, so the file also loads into PyTorch with
// model.load_state_dict(load_file(path), strict=False).
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "nets/io/safetensors.h"
#include "nets/optim/adam.h"
#include "nets/optim/ema.h"

namespace smokesvd::optim {

void saveCheckpoint(const std::filesystem::path& path, const NamedParameters& model, const Adam& adam,
                    const Ema* ema = nullptr, const std::map<std::string, std::string>& metadata = {});

// Restores everything saveCheckpoint wrote into the given model, optimiser and EMA (which must have the
// same parameters). Strict: a missing, unexpected or differently shaped tensor, a file that is no
// checkpoint, or an optimiser of the other kind (Adam / AdamW) is an Error and nothing is loaded.
// Returns the file's metadata.
std::map<std::string, std::string> loadCheckpoint(const std::filesystem::path& path, const NamedParameters& model,
                                                  Adam& adam, Ema* ema = nullptr);

// Whether `file` is a training checkpoint (its metadata's "format").
bool isCheckpoint(const io::SafetensorsFile& file);
// The EMA weights of a checkpoint under the model's own names ("ema.<parameter>" as "<parameter>"), with the
// checkpoint's metadata: the weights its run's model.safetensors would hold had it ended at that step. An
// Error naming `source` if the checkpoint has no EMA.
io::SafetensorsFile checkpointEmaWeights(const io::SafetensorsFile& file, const std::string& source);

}  // namespace smokesvd::optim
