// The six trained networks a reconstruction runs, loaded from a models folder (<models>/<network>/ with
// config.json and model.safetensors, as `smokesvd train` writes them; models/<preset>/ in the project
// ships them). Without `sideViews` (a reconstruction whose side view is the mirrored front view) the two
// SvDiff models are neither needed nor loaded. Errors name the folder, the network and, for weights of
// another architecture, every tensor that differs.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "nets/diffusion/schedule.h"
#include "pipeline/networks/density_generator.h"
#include "pipeline/networks/refiner.h"
#include "pipeline/networks/side_view_synthesizer.h"
#include "pipeline/networks/velocity_generator.h"
#include "pipeline/preset.h"

namespace smokesvd::reconstruct {

struct MethodModels {
  MethodModels(Context& context, const std::filesystem::path& folder, const Preset& preset, bool sideViews = true);

  std::unique_ptr<networks::SideViewSynthesizer> sideView, sideViewInit;  // null without side views
  std::unique_ptr<networks::DensityGenerator> coarse, fine;
  std::unique_ptr<networks::Refiner> refiner;
  std::unique_ptr<networks::VelocityGenerator> velocity;
  double refinerBeta = 22.5;   // NvRef's angular offset (its config's options.beta)
  diffusion::NoiseSchedule schedule = diffusion::NoiseSchedule::linear();  // SvDiff's
  diffusion::NoiseSchedule initSchedule = diffusion::NoiseSchedule::linear();
  std::map<std::string, std::string> hashes;  // network -> FNV-1a 64 of its model.safetensors (hex)
};

// The shipped weights of a preset: <project>/models/<preset>, found next to the executable's source tree
// (SMOKESVD_MODELS overrides).
std::filesystem::path defaultModelsFolder(const std::string& preset);

}  // namespace smokesvd::reconstruct
