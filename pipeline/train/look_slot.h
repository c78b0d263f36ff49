// The render look of a trainer's samples on the device (pipeline/render/renderer.h, RenderSettings::look):
// one [8] tensor that every recording of the trainer reads, refilled with each sample's look. Whether
// a look has a light selects the kernels, so a trainer keeps one recording per case (variant 0 unlit,
// 1 lit).
#pragma once

#include "pipeline/render/renderer.h"

namespace smokesvd::train {

class LookSlot {
 public:
  explicit LookSlot(Context& context);
  // Uploads `look` (step 1 and light step 1 are assumed, as the simulator renders) and returns 1 if it
  // has a light, else 0.
  int upload(const render::RenderSettings& look) const;
  // Settings to record with: the device look, and a light exactly when `lit`.
  render::RenderSettings settings(bool lit) const;

 private:
  Tensor look_;
};

}  // namespace smokesvd::train
