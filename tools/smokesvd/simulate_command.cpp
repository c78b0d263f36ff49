// `smokesvd simulate`: runs smoke scenes and writes every frame's density, velocity, inflow and orbit
// renders (docs/simulation.md).
//
//   smokesvd simulate --scene scene.json --out run/            one scene from a file
//   smokesvd simulate --scenes 100 --seed 1 --out data/        random scenes data/scene_0000 ...
//                     [--preset tiny|small|paper] [--resolution X,Y,Z] [--frames N]
//
// Interrupted runs resume from their last complete frame when started again with the same arguments.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include "pipeline/preset.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

struct SimulateArguments {
  std::string scene;
  int scenes = 0;
  uint64_t seed = 0;
  std::string preset = "small";
  std::vector<int64_t> resolution;
  int frames = 0;
  std::string out;
  bool noRender = false;
  bool overwrite = false;
  bool presetGiven = false;
};

std::string clock(double seconds) {
  const long total = std::lround(std::max(seconds, 0.0));
  char text[32];
  std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", total / 3600, total / 60 % 60, total % 60);
  return text;
}

// Prints one progress line per frame on stderr (rewritten in place on a terminal).
class ProgressLine {
 public:
  ProgressLine(int scenes, int framesPerScene)
      : scenes_(scenes), framesPerScene_(framesPerScene), terminal_(isatty(STDERR_FILENO) != 0) {}

  void update(int scene, const sim::RunProgress& p) {
    const double rate = p.seconds > 0 ? p.framesThisRun / p.seconds : 0;
    const int remaining = (p.frames - p.frame) + (scenes_ - scene - 1) * framesPerScene_;
    const double eta = rate > 0 ? remaining / rate : 0;
    char text[256];
    std::snprintf(text, sizeof text, "scene %d/%d  frame %d/%d  %.2f frames/s  ETA %s  (pressure: %d it, rel. residual %.1e%s)",
                  scene + 1, scenes_, p.frame, p.frames, rate, clock(eta).c_str(), p.report.pressureIterations,
                  p.report.relativeResidual, p.report.converged ? "" : ", NOT converged");
    std::cerr << (terminal_ ? "\r\033[K" : "") << text << (terminal_ ? "" : "\n") << std::flush;
  }
  void finishScene() {
    if (terminal_) std::cerr << "\n";
  }

 private:
  int scenes_, framesPerScene_;
  bool terminal_;
};

void simulate(const GlobalOptions& global, const SimulateArguments& args) {
  if (args.scene.empty() == (args.scenes == 0))
    throw Error("simulate: give either --scene FILE or --scenes N (random scenes)");
  if (!args.scene.empty() && (args.presetGiven || !args.resolution.empty()))
    throw Error("simulate: a scene file fixes its resolution; --preset and --resolution apply to random scenes");
  if (!args.resolution.empty() && args.resolution.size() != 3)
    throw Error("simulate: --resolution expects three cell counts X,Y,Z");

  std::vector<sim::Scene> scenes;
  std::vector<std::filesystem::path> directories;
  const std::filesystem::path out(args.out);
  if (!args.scene.empty()) {
    sim::Scene scene = sim::readScene(args.scene);
    if (args.frames > 0) scene.frames = args.frames;
    scenes.push_back(scene);
    directories.push_back(out);
  } else {
    const Preset& p = preset(args.preset);
    GridSize resolution = p.grid;
    if (!args.resolution.empty()) {
      for (int64_t side : args.resolution)
        if (side < 3 || side > 1024) throw Error("simulate: --resolution sides must be between 3 and 1024 cells");
      resolution = {.x = args.resolution[0], .y = args.resolution[1], .z = args.resolution[2]};
    }
    const int frames = args.frames > 0 ? args.frames : p.frames;
    for (int i = 0; i < args.scenes; ++i) {
      sim::Scene scene = sim::randomScene(args.seed + static_cast<uint64_t>(i), resolution, frames);
      scene.render.views = p.views;
      if (args.resolution.empty()) {
        scene.render.width = p.imageWidth;
        scene.render.height = p.imageHeight;
      }
      scenes.push_back(scene);
      char name[32];
      std::snprintf(name, sizeof name, "scene_%04d", i);
      directories.push_back(out / name);
    }
  }

  Context context(global.contextOptions());
  ProgressLine line(static_cast<int>(scenes.size()), scenes.front().frames);
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    sim::RunOptions options;
    options.render = !args.noRender;
    options.overwrite = args.overwrite;
    options.progress = [&line, i](const sim::RunProgress& p) { line.update(static_cast<int>(i), p); };
    const sim::RunResult result = sim::runScene(context, scenes[i], directories[i], options);
    line.finishScene();
    if (result.framesSimulated == 0 && result.complete)
      std::cerr << directories[i].string() << ": already complete, skipped\n";
    else if (result.resumed)
      std::cerr << directories[i].string() << ": resumed, " << result.framesSimulated << " frames simulated\n";
  }
}

void addSimulateCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static SimulateArguments args;
  CLI::App* command = app.add_subcommand("simulate", "simulate smoke scenes: fields (.npz) and orbit renders (.png) per frame");
  command->add_option("--scene", args.scene, "scene JSON file (docs/simulation.md)")->check(CLI::ExistingFile);
  command->add_option("--scenes", args.scenes, "draw this many random scenes")->check(CLI::PositiveNumber);
  command->add_option("--seed", args.seed, "seed of the first random scene (scene i uses seed + i)");
  command->add_option("--preset", args.preset, "resolution, views and frames of random scenes: tiny, small, paper")
      ->each([](const std::string&) { args.presetGiven = true; });
  command->add_option("--resolution", args.resolution, "grid cells X,Y,Z of random scenes (overrides the preset)")
      ->delimiter(',');
  command->add_option("--frames", args.frames, "frames per scene (overrides the preset or the scene file)")
      ->check(CLI::PositiveNumber);
  command->add_option("--out", args.out, "output directory")->required();
  command->add_flag("--no-render", args.noRender, "skip the orbit-view PNGs");
  command->add_flag("--overwrite", args.overwrite, "discard a previous run in the output directory instead of resuming it");
  command->callback([&global, &action] { action = [&global] { simulate(global, args); }; });
}

const bool registered = registerCommand({"simulate", addSimulateCommand});

}  // namespace
}  // namespace smokesvd::cli
