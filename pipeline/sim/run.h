// Running a scene into an output directory, frame by frame, resumable: after each frame's files the
// simulator state goes to checkpoint.npz (temporary name, then renamed); a later run of the same scene
// into the same directory restores it and continues with the next frame, so an interrupted run ends
// with exactly the files an uninterrupted one writes. A finished run leaves run.json and keeps its
// checkpoint, so the same scene with more frames extends it. Every file is listed in the run's manifest
// (run_files.h) before it is written; --overwrite deletes only those, and refuses a folder that is not a
// run.
#pragma once

#include <filesystem>
#include <functional>

#include "pipeline/sim/scene.h"
#include "pipeline/sim/simulator.h"
#include "runtime/context.h"

namespace smokesvd::sim {

struct RunProgress {
  int frame = 0;            // frames completed in this scene
  int frames = 0;           // frames of the scene
  int framesThisRun = 0;    // frames simulated since this call started (resumed frames excluded)
  double seconds = 0;       // wall time since this call started
  FrameReport report;       // the frame just completed
};

struct RunOptions {
  bool render = true;       // write the orbit-view PNGs of every frame
  bool overwrite = false;   // discard a previous run in the directory (its files only) instead of resuming it
  int maxFrames = -1;       // stop after this many frames in this call (-1: run to the end)
  std::function<void(const RunProgress&)> progress;  // called after every frame
};

struct RunResult {
  int framesSimulated = 0;  // in this call
  bool complete = false;    // every frame of the scene is written
  bool resumed = false;     // the call continued a previous run
};

RunResult runScene(Context& context, const Scene& scene, const std::filesystem::path& directory,
                   const RunOptions& options);

}  // namespace smokesvd::sim
