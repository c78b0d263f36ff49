// Presets: named sets of sizes every command starts from (`--preset tiny|small|paper`), each field
// overridable. `tiny` runs in seconds on lavapipe (tests), `small` trains on a 2-core CPU in about an
// hour, `paper` is the paper's setting (64x112x64 volumes, 16 views; GPU).
#pragma once

#include <string>
#include <vector>

#include "runtime/geometry.h"

namespace smokesvd {

struct Preset {
  std::string name;
  GridSize grid;                        // volume resolution in cells
  int imageWidth = 0, imageHeight = 0;  // rendered view size
  int views = 16;                       // orbit views on [0, 180) degrees
  int frames = 0;                       // frames per simulated scene
  // The networks' reference absorption per unit density per voxel, 0.3 at 64 cells across and scaled
  // with the width, so that a density looks the same at every preset. Densities the networks see and
  // produce are in these units (docs/models.md).
  float absorption = 0.3f;
};

// Throws Error listing the known presets if `name` is not one.
const Preset& preset(const std::string& name);
const std::vector<Preset>& presets();

}  // namespace smokesvd
