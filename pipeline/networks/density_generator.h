// G_rho as the pipeline uses it: the images of the 16 view slots (view_slots.h; a missing view is an
// image of zeros), each lifted along its camera rays into the volume (pipeline/render/lift.h), with a
// presence vector saying which slots hold a view, through the 3D UNet3+ to a density >= 0 in the
// networks' units (reference absorption of the preset, docs/models.md):
//   density [D, H, W] = UNet3+(lift(images) [1, 16, D, H, W], presence [1, 16])
#pragma once

#include <filesystem>
#include <memory>

#include "nets/models/unet3plus.h"
#include "pipeline/networks/network_config.h"
#include "pipeline/preset.h"
#include "pipeline/render/view_set.h"

namespace smokesvd::networks {

struct DensityOutput {
  Var density;                   // [D, H, W]
  std::vector<Var> supervision;  // deep-supervision heads, each [D, H, W] (training only)
};

class DensityGenerator {
 public:
  DensityGenerator(Context& context, const models::UNet3PlusConfig& config, const Preset& preset);
  // images [16, 1, h, w]; presence [16] (or [1, 16]) of 0 and 1.
  DensityOutput forward(Tape& tape, const Var& images, const Var& presence, bool deepSupervision = false);
  // The images [16, 1, h, w] with `images` [1, 1, h, w] in their slots and zeros in every other slot,
  // differentiable in each given image (e.g. front and side for the coarse G_rho).
  Var slotImages(Tape& tape, const std::vector<std::pair<int, Var>>& images) const;
  models::UNet3Plus& net() { return *net_; }
  const render::ViewSet& views() const { return views_; }
  const GridSize& grid() const { return grid_; }
  const Preset& preset() const { return preset_; }

 private:
  Preset preset_;
  std::shared_ptr<models::UNet3Plus> net_;
  render::ViewSet views_;
  GridSize grid_;
};

// The trained `network` (grho-coarse or grho-fine) of the folder `models` (trained_model.h), loaded and
// frozen: the density generator a trainer makes its inputs or guidance through.
std::unique_ptr<DensityGenerator> loadFrozenDensityGenerator(Context& context, const std::filesystem::path& models,
                                                             Network network, const Preset& preset);

}  // namespace smokesvd::networks
