// Density volumes from files, for `smokesvd render` and later stages.
//
// Accepted: .npy with shape [D, H, W], [D, H, W, 1], [1, D, H, W] or [1, 1, D, H, W] (z, y, x; float32 or
// int32), and .npz holding such an array under `key` if given, else the first of "density" (smokesvd),
// "data" (ScalarFlow: [z, y, x, 1]), "arr_0" (mantaflow's numpy export) that exists, else its only member.
// A [z, y, x, 3] array is a velocity, not a density, and is refused with that explanation; so are grids
// beyond checkGridSize (runtime/geometry.h) and NaN or infinite values (the first is named).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "runtime/geometry.h"

namespace smokesvd::media {

struct DensityVolume {
  GridSize grid;
  std::vector<float> values;  // [D, H, W], x fastest
};

DensityVolume readDensityVolume(const std::filesystem::path& path, const std::string& key = "");

}  // namespace smokesvd::media
