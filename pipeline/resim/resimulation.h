// `smokesvd resim`: a reconstruction run forward again through the simulator (pipeline/sim), driven by its
// own velocity and inflow (pipeline/resim/reconstructed_drive.h), with edits: obstacles inserted at a
// frame, forces, vorticity confinement, a finer grid, more frames than the video had. Output, in the
// simulator's layout (pipeline/sim/outputs.h, docs/applications.md):
//   OUT/scene.json                the re-simulation's domain: grid, boundaries, obstacles, forces, look
//   OUT/flags.npz                 the cells' flags at frame 0
//   OUT/fields/{density,velocity,inflow}_NNNN.npz
//   OUT/forces/force_NN.npz       the force fields on the re-simulation's grid (when --force FILE)
//   OUT/renders/view_VV/NNNN.png  16 orbit views (the reconstruction's cameras)
//   OUT/front.mp4, OUT/side.mp4   views 0 and 8 (when ffmpeg is there)
//   OUT/run.json                  "command": "smokesvd resim", the source, the options, the drive, per-frame
//                                 projection reports and (at --upres 1) the departure from the reconstruction
// Frame 0 is the reconstruction's frame 0 (upsampled, with the edits active at frame 0 applied). Every file is
// written under a temporary name and renamed; run.json says "complete" only at the end.
#pragma once

#include <filesystem>
#include <vector>

#include "pipeline/resim/edits.h"
#include "runtime/context.h"

namespace smokesvd::resim {

struct ResimOptions {
  std::filesystem::path source;  // a complete reconstruction (run.json "command": "smokesvd reconstruct")
  std::filesystem::path out;
  int frames = -1;               // frames of the re-simulation (-1: as many as the reconstruction has)
  std::vector<ObstacleEdit> obstacles;
  std::vector<ForceEdit> forces;
  int upres = 1;                 // 1, 2, 3 or 4: cells per reconstruction cell along each axis
  double vorticity = 0;          // vorticity confinement strength on the re-simulation's grid
  double inflowScale = 1;
  bool overwrite = false;        // replace a previous re-simulation in `out`
  bool quiet = false;
  bool videos = true;
};

// How far the re-simulated density is from the reconstructed one, over the reconstruction's open cells.
struct FrameDeparture {
  int frame = 0;
  double relativeL2 = 0;  // ||rho_resim - rho_recon|| / ||rho_recon||
  double maxAbs = 0;      // max |rho_resim - rho_recon|
};

struct ResimResult {
  int frames = 0;
  double seconds = 0;
  int maxPressureIterations = 0;
  bool converged = true;                     // every projection reached its tolerance
  std::vector<FrameDeparture> departures;    // frames the reconstruction has too, at --upres 1
};

ResimResult runResimulation(Context& context, const ResimOptions& options);

}  // namespace smokesvd::resim
