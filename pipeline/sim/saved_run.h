// Reading a finished run folder in the simulator's layout (pipeline/sim/outputs.h): what `smokesvd simulate`,
// `smokesvd reconstruct` and `smokesvd resim` write. run.json says which command wrote it ("command"; a
// simulation's run.json has none) and that the run is complete; scene.json gives the grid, the boundaries
// and the look; the fields are read frame by frame. Errors name the folder and what is missing.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/sim/scene.h"

namespace smokesvd::sim {

struct SavedRun {
  std::filesystem::path root;
  std::string command;     // "smokesvd simulate", "smokesvd reconstruct" or "smokesvd resim"
  nlohmann::json run;      // run.json
  Scene scene;             // scene.json
  int frames = 0;          // frames written (every one has density, velocity and inflow files)
  double frameRate = 30;   // frames per second of the footage (30 when the run does not say)
  // The NeRF-style calibration file that placed the box in the world (calibrated footage), if any.
  std::optional<std::filesystem::path> calibration;

  GridSize grid() const { return scene.resolution; }
  std::filesystem::path field(const std::string& name, int frame) const;  // fields/<name>_NNNN.npz
  std::vector<float> density(int frame) const;   // [D, H, W]
  std::vector<float> inflow(int frame) const;    // [D, H, W]
  std::vector<float> velocity(int frame) const;  // planar MAC [3, D, H, W]
};

// Error unless `root` holds a complete run: run.json (complete), scene.json and the fields of every frame.
SavedRun readSavedRun(const std::filesystem::path& root);

}  // namespace smokesvd::sim
