// `smokesvd resim RECON_DIR --out DIR`: a reconstruction run forward again through the simulator, driven by its
// own velocity and inflow, with edits (docs/applications.md):
//
//   smokesvd resim recon/ --out again/                                  no edits: follows the reconstruction
//   smokesvd resim recon/ --out ball/ --obstacle sphere:32,60,32,8@50   a sphere appears at frame 50
//   smokesvd resim recon/ --out wind/ --force uniform:0.02,0,0@20:80    a side wind on the smoke
//   smokesvd resim recon/ --out fine/ --upres 2 --vorticity 0.1 --frames 300
//
// Positions, radii and accelerations are in cells of the reconstruction's grid (and per step, one step a frame)
// whatever --upres is.
#include <iostream>

#include "pipeline/progress.h"
#include "pipeline/resim/resimulation.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

struct ResimArguments {
  std::string source, out;
  int frames = -1, upres = 1;
  std::vector<std::string> obstacles, forces;
  double vorticity = 0, inflowScale = 1;
  bool overwrite = false, noVideos = false;
};

void runResim(const GlobalOptions& global, const ResimArguments& a) {
  resim::ResimOptions o;
  o.source = a.source;
  o.out = a.out;
  o.frames = a.frames;
  for (const std::string& text : a.obstacles) o.obstacles.push_back(resim::parseObstacle(text));
  for (const std::string& text : a.forces) o.forces.push_back(resim::parseForce(text));
  o.upres = a.upres;
  o.vorticity = a.vorticity;
  o.inflowScale = a.inflowScale;
  o.overwrite = a.overwrite;
  o.videos = !a.noVideos;
  Context context(global.contextOptions());
  const resim::ResimResult r = resim::runResimulation(context, o);
  std::cerr << a.out << ": " << r.frames << " frames in " << formatDuration(r.seconds) << " (pressure: at most "
            << r.maxPressureIterations << " iterations" << (r.converged ? "" : ", some projections did NOT converge") << ")";
  if (r.departures.size() > 1)
    std::cerr << "; departure from the reconstruction (relative L2) " << r.departures[1].relativeL2 << " at frame 1, "
              << r.departures.back().relativeL2 << " at frame " << r.departures.back().frame;
  std::cerr << "\n";
}

void addResimCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static ResimArguments a;
  CLI::App* c = app.add_subcommand("resim", "re-simulate a reconstruction with edits: obstacles, forces, a finer grid, more frames");
  c->add_option("reconstruction", a.source, "a folder written by smokesvd reconstruct")->required();
  c->add_option("--out", a.out, "output folder (the simulator's layout, renders and mp4)")->required();
  c->add_option("--frames", a.frames, "frames to simulate (default: the reconstruction's; more continue past the video)")
      ->check(wholeNumber(1, sim::kMaxFrames));
  c->add_option("--obstacle", a.obstacles, "sphere:X,Y,Z,R[@A[:B]]: a sphere (reconstruction cells) from frame A (to B); repeatable")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c->add_option("--force", a.forces,
                "uniform:AX,AY,AZ[@A[:B]] (an acceleration on the smoke, cells/step^2) or FIELD.npz|.npy[@A[:B]] "
                "(a cell-centred acceleration [z,y,x,3] on the reconstruction's grid); repeatable")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c->add_option("--upres", a.upres, "cells per reconstruction cell along each axis: 1 (default) to 4")->check(wholeNumber(1, 4));
  c->add_option("--vorticity", a.vorticity, "vorticity confinement strength (default 0; e.g. 0.1 with --upres 2)")
      ->check(number(0, 1e3));
  c->add_option("--inflow-scale", a.inflowScale, "multiplies the reconstructed inflow (default 1)")->check(number(0, 1e6));
  c->add_flag("--overwrite", a.overwrite, "replace a re-simulation in --out");
  c->add_flag("--no-videos", a.noVideos, "skip front.mp4 and side.mp4");
  c->callback([&global, &action] { action = [&global] { runResim(global, a); }; });
}

const bool registered = registerCommand({"resim", addResimCommand});

}  // namespace
}  // namespace smokesvd::cli
