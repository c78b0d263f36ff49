// The files of a reconstruction run (reconstruction.h lists them), each written under a temporary name
// and renamed. --overwrite clears exactly these files and folders, and only in a folder whose run.json
// says it is a reconstruction; a folder that holds anything else is refused.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/preset.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::reconstruct {

class RunFolder {
 public:
  explicit RunFolder(std::filesystem::path root);
  // Error unless the folder is absent or empty (it is not a reconstruction's, and it is not ours to fill).
  void requireEmptyOrAbsent() const;
  void clear() const;             // removes every file and folder a run writes
  void prepare() const;           // creates the folders (Error naming the folder if it cannot)
  void removeTemporaries() const; // *.tmp left by an interrupted run

  void writeFlags(const std::vector<float>& flags, const GridSize& grid) const;
  // density, inflow [D, H, W]; views [16, 1, h, w]; side and front [1, 1, h, w] (device tensors).
  void writeFrame(int frame, const Tensor& density, const Tensor& inflow, const Tensor& views, const Tensor& side,
                  const Tensor& front) const;
  // velocity [3, D, H, W] MAC, planar (undefined: zeros of the grid's size).
  void writeVelocity(int frame, const Tensor& velocity) const;
  // input.mp4, side.mp4, orbit.mp4 (one turn over the clip) and contact.png; what was written.
  nlohmann::json writeSummaries(Context& context, int frames, double frameRate, const render::RenderSettings& look,
                                const Preset& preset) const;

 private:
  std::filesystem::path root_;
};

}  // namespace smokesvd::reconstruct
