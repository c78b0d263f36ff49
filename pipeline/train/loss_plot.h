// loss.png: the loss terms of a run against the step, on a log scale (one colour per term, the total in
// white, each smoothed over 1 % of the run), with decade grid lines labelled 1e-3, 1e-2, ...
#pragma once

#include <filesystem>

#include "pipeline/train/loss_log.h"

namespace smokesvd::train {

// Plots every column of `log` from `firstColumn` on (step is column 0) and writes the PNG atomically.
void plotLosses(const std::filesystem::path& path, const CsvLog& log, std::size_t firstColumn);

}  // namespace smokesvd::train
