#include "pipeline/sim/run.h"

#include <chrono>
#include <fstream>

#include "pipeline/sim/frame_render.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

namespace fs = std::filesystem;

bool isComplete(const fs::path& directory) {
  std::ifstream in(directory / "run.json");
  if (!in) return false;
  const nlohmann::json status = nlohmann::json::parse(in, nullptr, false);
  return status.is_object() && status.value("complete", false);
}

void writeRunStatus(const fs::path& directory, int frames) {
  const fs::path temporary = directory / "run.json.tmp";
  {
    std::ofstream out(temporary);
    out << nlohmann::json{{"complete", true}, {"frames", frames}}.dump(2) << "\n";
    if (!out) throw Error(temporary.string() + ": cannot write the run status");
  }
  fs::rename(temporary, directory / "run.json");
}

// True if the directory already holds this scene; Error if it holds another one.
bool holdsScene(const fs::path& directory, const Scene& scene) {
  const fs::path path = directory / "scene.json";
  if (!fs::exists(path)) return false;
  if (sceneToJson(readScene(path)) != sceneToJson(scene))
    throw Error(path.string() + " describes a different scene; pass --overwrite to replace that run or choose "
                "another output directory");
  return true;
}

}  // namespace

RunResult runScene(Context& context, const Scene& scene, const fs::path& directory, const RunOptions& options) {
  RunResult result;
  fs::create_directories(directory);
  if (options.overwrite) {
    for (const char* stale : {"run.json", "checkpoint.npz", "flags.npz", "fields", "renders"}) fs::remove_all(directory / stale);
  } else if (holdsScene(directory, scene) && isComplete(directory)) {
    result.complete = true;
    return result;
  }
  writeScene(directory / "scene.json", scene);

  Simulator simulator(context, scene);
  if (!options.overwrite) {
    if (std::optional<SimulatorState> state = readCheckpoint(directory, scene)) {
      simulator.restore(*state);
      result.resumed = true;
    }
  }
  if (simulator.frame() == 0) writeFlags(directory, simulator);
  std::optional<FrameRenderer> renderer;
  if (options.render && scene.render.enabled) renderer.emplace(scene);

  const auto start = std::chrono::steady_clock::now();
  while (simulator.frame() < scene.frames && (options.maxFrames < 0 || result.framesSimulated < options.maxFrames)) {
    const FrameReport report = simulator.advanceFrame();
    writeFrameFields(directory, simulator);
    if (renderer) renderer->write(directory, simulator);
    writeCheckpoint(directory, simulator);
    ++result.framesSimulated;
    if (options.progress) {
      RunProgress progress;
      progress.frame = simulator.frame();
      progress.frames = scene.frames;
      progress.framesThisRun = result.framesSimulated;
      progress.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      progress.report = report;
      options.progress(progress);
    }
  }
  if (simulator.frame() == scene.frames) {
    writeRunStatus(directory, scene.frames);
    fs::remove(directory / "checkpoint.npz");
    result.complete = true;
  }
  return result;
}

}  // namespace smokesvd::sim
