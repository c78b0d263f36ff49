// The side-view sampling flags that `smokesvd reconstruct` and `smokesvd rollout` share, bound to a
// reconstruct::SideViewOptions (its defaults are the flags' defaults): --seed, --ddim-steps, --init-steps,
// --eta, --side-view-start, --side-samples, --init-share.
#pragma once

#include <CLI/CLI.hpp>

#include "pipeline/reconstruct/side_view_stage.h"

namespace smokesvd::cli {

void addSideViewSamplingFlags(CLI::App& command, reconstruct::SideViewOptions& options);

}  // namespace smokesvd::cli
