// The edits of `smokesvd resim` as the command line spells them, in the reconstruction's units (cells of
// its grid, accelerations in cells per step², one step per frame), whatever --upres is:
//   sphere:X,Y,Z,R[@A[:B]]    an obstacle: a sphere centred at grid point (X, Y, Z) with radius R, from
//                             frame A (0 if absent) up to frame B (excluded; absent: to the end)
//   uniform:AX,AY,AZ[@A[:B]]  a force: the same acceleration on every fluid face
//   FILE[@A[:B]]              a force: a cell-centred acceleration field [z, y, x, 3] of the reconstruction's
//                             grid, .npy or .npz (member "force", or its only member)
// Errors name the option, the text and what was expected.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/sim/scene.h"

namespace smokesvd::resim {

struct ObstacleEdit {
  std::string text;  // as given, for messages
  Vec3 centre{0, 0, 0};
  double radius = 0;
  sim::FrameRange frames;
};

struct ForceEdit {
  std::string text;
  bool uniform = false;
  Vec3 acceleration{0, 0, 0};  // uniform
  std::filesystem::path file;  // a field
  sim::FrameRange frames;
};

ObstacleEdit parseObstacle(const std::string& text);
ForceEdit parseForce(const std::string& text);

}  // namespace smokesvd::resim
