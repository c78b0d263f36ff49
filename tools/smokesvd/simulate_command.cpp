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
#include <optional>

#include "pipeline/preset.h"
#include "pipeline/sim/random_scene.h"
#include "pipeline/sim/run.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"
#include "tools/smokesvd/option_checks.h"

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

constexpr int kMaxScenes = 100000;

void simulate(const GlobalOptions& global, const SimulateArguments& args) {
  if (args.scene.empty() == (args.scenes == 0))
    throw Error("simulate: give either --scene FILE or --scenes N (random scenes)");
  if (!args.scene.empty() && (args.presetGiven || !args.resolution.empty()))
    throw Error("simulate: a scene file fixes its resolution; --preset and --resolution apply to random scenes");
  if (!args.resolution.empty() && args.resolution.size() != 3)
    throw Error("simulate: --resolution expects three cell counts X,Y,Z");
  if (args.scenes > 0 && args.seed > static_cast<uint64_t>(INT64_MAX) - static_cast<uint64_t>(args.scenes))
    throw Error("simulate: --seed plus --scenes must stay below 2^63 (the seeds scene.json can hold)");

  // Scenes are made one at a time as the run reaches them (a list of a million is never built).
  const std::filesystem::path out(args.out);
  std::optional<sim::Scene> fromFile;
  GridSize resolution;
  int frames = 0;
  const Preset* p = nullptr;
  if (!args.scene.empty()) {
    fromFile = sim::readScene(args.scene);
    if (args.frames > 0) fromFile->frames = args.frames;
    frames = fromFile->frames;
  } else {
    p = &preset(args.preset);
    resolution = p->grid;
    if (!args.resolution.empty()) {
      resolution = {.x = args.resolution[0], .y = args.resolution[1], .z = args.resolution[2]};
      checkGridSize(resolution, "simulate --resolution");
    }
    frames = args.frames > 0 ? args.frames : p->frames;
  }
  const int count = fromFile ? 1 : args.scenes;
  auto sceneAt = [&](int i) {
    if (fromFile) return *fromFile;
    sim::Scene scene = sim::randomScene(args.seed + static_cast<uint64_t>(i), resolution, frames);
    scene.render.views = p->views;
    if (args.resolution.empty()) {
      scene.render.width = p->imageWidth;
      scene.render.height = p->imageHeight;
    }
    return scene;
  };
  auto directoryAt = [&](int i) {
    if (fromFile) return out;
    char name[32];
    std::snprintf(name, sizeof name, "scene_%04d", i);
    return out / name;
  };

  Context context(global.contextOptions());
  ProgressLine line(count, frames);
  for (int i = 0; i < count; ++i) {
    const sim::Scene scene = sceneAt(i);
    const std::filesystem::path directory = directoryAt(i);
    sim::RunOptions options;
    options.render = !args.noRender;
    options.overwrite = args.overwrite;
    options.progress = [&line, i](const sim::RunProgress& progress) { line.update(i, progress); };
    const sim::RunResult result = sim::runScene(context, scene, directory, options);
    line.finishScene();
    if (result.framesSimulated == 0 && result.complete)
      std::cerr << directory.string() << ": already complete, skipped\n";
    else if (result.resumed)
      std::cerr << directory.string() << ": resumed, " << result.framesSimulated << " frames simulated\n";
  }
}

void addSimulateCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static SimulateArguments args;
  CLI::App* command = app.add_subcommand("simulate", "simulate smoke scenes: fields (.npz) and orbit renders (.png) per frame");
  command->add_option("--scene", args.scene, "scene JSON file (docs/simulation.md)");
  command->add_option("--scenes", args.scenes, "draw this many random scenes")->check(wholeNumber(1, kMaxScenes));
  command->add_option("--seed", args.seed, "seed of the first random scene (scene i uses seed + i)")
      ->check(wholeNumber(0, INT64_MAX));
  command->add_option("--preset", args.preset, "resolution, views and frames of random scenes: tiny, small, paper")
      ->each([](const std::string&) { args.presetGiven = true; });
  command->add_option("--resolution", args.resolution, "grid cells X,Y,Z of random scenes (overrides the preset)")
      ->delimiter(',')
      ->check(wholeNumber(sim::kMinSceneSide, kMaxGridSide));
  command->add_option("--frames", args.frames, "frames per scene (overrides the preset or the scene file)")
      ->check(wholeNumber(1, sim::kMaxFrames));
  command->add_option("--out", args.out, "output directory")->required();
  command->add_flag("--no-render", args.noRender, "skip the orbit-view PNGs");
  command->add_flag("--overwrite", args.overwrite,
                    "discard a previous run in the output directory (only the files a run wrote) instead of resuming it");
  command->callback([&global, &action] { action = [&global] { simulate(global, args); }; });
}

const bool registered = registerCommand({"simulate", addSimulateCommand});

}  // namespace
}  // namespace smokesvd::cli
