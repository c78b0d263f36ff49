// G_u as the pipeline uses it: two consecutive densities (networks' units) in, the cell-centred velocity
// that carries the first toward the second out (cells per step), through the 3D UNet3+:
//   velocity [3, D, H, W] = UNet3+(cat(rho_t, rho_t+1) [1, 2, D, H, W])
// The simulator's MAC layout follows from diff::centredToMac (docs/conventions.md).
#pragma once

#include <memory>
#include <vector>

#include "nets/models/unet3plus.h"
#include "pipeline/preset.h"

namespace smokesvd::networks {

struct VelocityOutput {
  Var velocity;                  // [3, D, H, W], centred
  std::vector<Var> supervision;  // deep-supervision heads, each [3, D, H, W] (training only)
};

class VelocityGenerator {
 public:
  VelocityGenerator(Context& context, const models::UNet3PlusConfig& config, const Preset& preset);
  // current, next: [D, H, W].
  VelocityOutput forward(Tape& tape, const Var& current, const Var& next, bool deepSupervision = false);
  models::UNet3Plus& net() { return *net_; }

 private:
  std::shared_ptr<models::UNet3Plus> net_;
  GridSize grid_;
};

}  // namespace smokesvd::networks
