#include "tools/smokesvd/side_view_flags.h"

#include <cstdint>
#include <string>

#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {

void addSideViewSamplingFlags(CLI::App& command, reconstruct::SideViewOptions& options) {
  command.add_option("--seed", options.seed, "seed of the side-view sampling (frame t samples with seed + t)")
      ->check(wholeNumber(0, INT64_MAX));
  command.add_option("--ddim-steps", options.steps, "DDIM steps per side view (default " + std::to_string(options.steps) + ")")
      ->check(wholeNumber(1, 10000));
  command.add_option("--init-steps", options.initSteps,
                     "DDIM steps for frames 0 and 1 (default " + std::to_string(options.initSteps) + ")")
      ->check(wholeNumber(1, 10000));
  command.add_option("--eta", options.eta, "DDIM eta: 0 deterministic, 1 ancestral (default 1)")->check(number(0, 100));
  command.add_option("--side-view-start", options.start,
                     "DDIM start step: -1 samples from pure noise (the paper), lower from the mirrored front view noised "
                     "to that step (default " + std::to_string(options.start) + "; docs/reconstruction.md)")
      ->check(wholeNumber(-1, 100000));
  command.add_option("--side-samples", options.samples,
                     "the side view is the mean of this many DDIM samples (default " + std::to_string(options.samples) +
                         "; docs/reconstruction.md)")
      ->check(wholeNumber(1, 1000));
  command.add_option("--init-share", options.initShare,
                     "frames 2 on: the share of SvDiff-init's history-free estimate in the side view (default 0, the "
                     "paper; 1: no history; docs/reconstruction.md)")
      ->check(number(0, 1));
}

}  // namespace smokesvd::cli
