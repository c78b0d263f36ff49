#include "pipeline/sim/run.h"

#include <algorithm>
#include <chrono>
#include <fstream>

#include "nets/io/file_io.h"
#include "pipeline/sim/frame_render.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/run_files.h"
#include "runtime/error.h"

namespace smokesvd::sim {
namespace {

namespace fs = std::filesystem;

// The frames a run in `directory` has written, per its run.json (0 if it has none).
int framesWritten(const fs::path& directory) {
  std::ifstream in(directory / "run.json");
  if (!in) return 0;
  const nlohmann::json status = nlohmann::json::parse(in, nullptr, false);
  if (!status.is_object() || status.find("complete") == status.end() || status["complete"] != true) return 0;
  const auto frames = status.find("frames");
  return frames != status.end() && frames->is_number_integer() ? static_cast<int>(std::clamp<int64_t>(frames->get<int64_t>(), 0, kMaxFrames)) : 0;
}

void writeRunStatus(RunFiles& files, int frames) {
  io::writeAtomically(files.add("run.json"), [&](const fs::path& temporary) {
    std::ofstream out(temporary);
    out << nlohmann::json{{"complete", true}, {"frames", frames}}.dump(2) << "\n";
    if (!out) throw Error(temporary.string() + ": cannot write the run status");
  });
}

// The scene as it is compared for resuming: everything but its frame count, which a run may extend.
nlohmann::json withoutFrames(const Scene& scene) {
  nlohmann::json json = sceneToJson(scene);
  json.erase("frames");
  return json;
}

// True if the directory already holds this scene (of any frame count); Error if it holds another one.
bool holdsScene(const fs::path& directory, const Scene& scene) {
  const fs::path path = directory / "scene.json";
  if (!fs::exists(path)) return false;
  if (withoutFrames(readScene(path)) != withoutFrames(scene))
    throw Error(path.string() + " describes a different scene; pass --overwrite to replace that run or choose "
                "another output directory (to add frames to that run, give --scene " + path.string() + " --frames N)");
  return true;
}

}  // namespace

RunResult runScene(Context& context, const Scene& scene, const fs::path& directory, const RunOptions& options) {
  RunResult result;
  if (options.overwrite) RunFiles::remove(directory);
  RunFiles files(directory);
  files.removeTemporaries();
  if (holdsScene(directory, scene) && framesWritten(directory) >= scene.frames) {
    result.complete = true;
    return result;
  }
  Simulator simulator(context, scene);  // reads the force fields: a bad one stops the run before any file
  writeScene(files.add("scene.json"), scene);
  if (std::optional<SimulatorState> state = readCheckpoint(directory, scene)) {
    simulator.restore(*state);
    result.resumed = true;
  }
  if (simulator.frame() == 0) writeFlags(files, simulator);
  std::optional<FrameRenderer> renderer;
  if (options.render && scene.render.enabled) renderer.emplace(scene);

  const auto start = std::chrono::steady_clock::now();
  while (simulator.frame() < scene.frames && (options.maxFrames < 0 || result.framesSimulated < options.maxFrames)) {
    const FrameReport report = simulator.advanceFrame();
    writeFrameFields(files, simulator);
    if (renderer) renderer->write(files, simulator);
    writeCheckpoint(files, simulator);
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
    writeRunStatus(files, scene.frames);
    result.complete = true;
  }
  return result;
}

}  // namespace smokesvd::sim
