// `smokesvd reconstruct`: one video in; per frame the 3D density, the MAC velocity and the inflow, the
// 16 refined views and the side view out, in the simulator's file layout (docs/reconstruction.md):
//   OUT/scene.json                 the box: resolution, boundaries, the look to render the result with
//   OUT/flags.npz                  the cells' flags (walls, open top), as the simulator writes them
//   OUT/fields/{density,velocity,inflow}_NNNN.npz
//   OUT/renders/view_VV/NNNN.png   the 16 views (0: the front view, 8: the synthesised side, others refined)
//   OUT/input/NNNN.png             the input as its camera saw it (for calibrated footage the crop, before
//                                  rectification; view_00 is the rectified front view)
//   OUT/side/NNNN.png
//   OUT/input.mp4, side.mp4, orbit.mp4, contact.png   (when the run is complete)
//   OUT/run.json                   preset, model hashes, device, options, input mapping, stage times
//   OUT/checkpoint.npz             while a run is in progress (--resume continues at the next frame)
// Frames are processed in order (stages of docs/reconstruction.md); each frame's files are written under
// temporary names and renamed, then the checkpoint, so an interrupted run resumed with --resume gives the
// files of an uninterrupted one.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include "pipeline/reconstruct/density_stage.h"
#include "pipeline/reconstruct/front_views.h"
#include "pipeline/reconstruct/motion_stage.h"
#include "pipeline/reconstruct/polish_stage.h"
#include "pipeline/reconstruct/side_view_stage.h"
#include "runtime/context.h"

namespace smokesvd::reconstruct {

struct ReconstructOptions {
  InputOptions input;
  std::filesystem::path out;
  std::filesystem::path models;  // empty: the shipped weights of the preset
  std::string preset = "small";
  bool resume = false, overwrite = false;
  bool quiet = false;
  bool videos = true;            // input/side/orbit mp4 and the contact sheet at the end
  int stopAfter = -1;            // stop after this many frames in this call, as if interrupted
  SideViewOptions sideView;
  // Side views given rather than synthesised (an oracle for ablations, or a second camera at 90°): read
  // like the input (from the same first frame, with the same intensity option) with box framing; one per
  // front view.
  std::filesystem::path sideViews;
  DensityOptions density;
  MotionOptions motion;
  PolishOptions polish;
};

struct ReconstructResult {
  int frames = 0;            // frames of the clip
  int framesThisCall = 0;
  bool complete = false;
  double seconds = 0;        // over every call
  std::map<std::string, double> stageSeconds;
};

ReconstructResult runReconstruction(Context& context, const ReconstructOptions& options);

}  // namespace smokesvd::reconstruct
