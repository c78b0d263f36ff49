// `smokesvd demo`: the method end to end on a plume no shipped network was trained on. It simulates the
// plume (random scene seed 7, which the training scenes' seeds 1000-1119 do not include) at the small
// preset, renders its front view with the networks' reference look into a video, reconstructs that video
// with the shipped weights three times -- the full method, the mirrored front view as the side view,
// and without refinement -- and compares each with the simulated truth: render PSNR at the input view,
// the side view and four novel views (45, 67.5, 112.5, 135 degrees), and the density RMSE, beside the
// trivial floors (an all-black image; the input view used as the other view, mirrored for the side).
//   DIR/truth/          the simulation (scene.json, fields/) and front.mp4
//   DIR/full/, DIR/mirror-side/, DIR/no-refinement/   the reconstructions
//   DIR/demo.json, DIR/demo.md                          the comparison
#pragma once

#include <filesystem>
#include <string>

#include "runtime/context.h"

namespace smokesvd::reconstruct {

struct DemoOptions {
  std::filesystem::path out = "smokesvd-demo";
  std::filesystem::path models;  // empty: the shipped weights
  std::string preset = "small";
  int frames = 40;
  uint64_t seed = 7;
  bool quiet = false;
};

// Returns the comparison table (markdown), also written to DIR/demo.md.
std::string runDemo(Context& context, const DemoOptions& options);

}  // namespace smokesvd::reconstruct
