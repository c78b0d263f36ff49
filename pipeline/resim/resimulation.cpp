#include "pipeline/resim/resimulation.h"

#include <chrono>
#include <cmath>
#include <fstream>

#include "nets/io/file_io.h"
#include "nets/io/json_file.h"
#include "nets/io/npy.h"
#include "pipeline/media/image.h"
#include "pipeline/media/video.h"
#include "pipeline/physics/grid.h"
#include "pipeline/progress.h"
#include "pipeline/resim/reconstructed_drive.h"
#include "pipeline/resim/upsample.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/frame_render.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/saved_run.h"
#include "pipeline/sim/simulator.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::resim {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

const std::vector<std::string>& outputNames() {
  static const std::vector<std::string> names{"run.json", "scene.json", "flags.npz", "fields", "renders",
                                              "forces",   "front.mp4",  "side.mp4"};
  return names;
}

std::string boxText(const GridSize& g) {
  return "[0, " + std::to_string(g.x) + "] x [0, " + std::to_string(g.y) + "] x [0, " + std::to_string(g.z) + "]";
}

void requireStartsInRun(const sim::FrameRange& frames, int total, const std::string& what) {
  if (frames.first >= total)
    throw Error(what + ": starts at frame " + std::to_string(frames.first) + ", but the re-simulation has frames 0.." +
                std::to_string(total - 1));
}

// The obstacle on the re-simulation's grid; Error if it lies outside the box or covers no cell of it.
sim::Obstacle obstacleOnGrid(const ObstacleEdit& edit, const sim::Scene& scene, const GridSize& coarse, int upres,
                             int total) {
  const std::string what = "--obstacle " + edit.text;
  const Vec3& c = edit.centre;
  if (c[0] < 0 || c[0] > static_cast<double>(coarse.x) || c[1] < 0 || c[1] > static_cast<double>(coarse.y) || c[2] < 0 ||
      c[2] > static_cast<double>(coarse.z))
    throw Error(what + ": the centre lies outside the reconstruction's box " + boxText(coarse) + " (cells)");
  requireStartsInRun(edit.frames, total, what);
  sim::Obstacle obstacle;
  obstacle.shape.kind = physics::SourceShape::Sphere;
  obstacle.shape.centre = c * static_cast<double>(upres);
  obstacle.shape.size = {edit.radius * upres, 0, 0};
  obstacle.frames = edit.frames;
  sim::Scene alone = scene;
  alone.obstacles = {obstacle};
  const std::vector<float> with = sim::sceneFlags(alone, obstacle.frames.first);
  alone.obstacles.clear();
  const std::vector<float> without = sim::sceneFlags(alone, 0);
  if (with == without) throw Error(what + ": covers no cell of the box (a larger radius, or a centre inside it)");
  return obstacle;
}

// A force field file as planar host values [3, D, H, W] of the reconstruction's grid.
std::vector<float> readForceField(const ForceEdit& edit, const GridSize& grid) {
  const std::string what = "--force " + edit.text;
  if (!fs::exists(edit.file)) throw Error(what + ": no such file");
  io::NpyArray array;
  if (edit.file.extension() == ".npz") {
    const std::map<std::string, io::NpyArray> arrays = io::readNpz(edit.file);
    if (arrays.contains("force")) array = arrays.at("force");
    else if (arrays.size() == 1) array = arrays.begin()->second;
    else throw Error(what + ": the .npz holds several arrays and none is called 'force'");
  } else {
    array = io::readNpy(edit.file);
  }
  const Shape expected{grid.z, grid.y, grid.x, 3};
  if (array.shape != expected)
    throw Error(what + ": shape " + toString(array.shape) + "; a force field is a cell-centred acceleration " +
                toString(expected) + " (z, y, x, component) on the reconstruction's grid");
  const std::vector<float> interleaved = array.toFloat();
  const std::size_t cells = interleaved.size() / 3;
  std::vector<float> planar(interleaved.size());
  for (std::size_t i = 0; i < cells; ++i)
    for (std::size_t a = 0; a < 3; ++a) planar[a * cells + i] = interleaved[3 * i + a];
  return planar;
}

// The sum of the uniform forces per frame as keyframes (exact at every frame: each change is a step
// between two consecutive frames), times `upres`.
sim::Keyframes<Vec3> uniformForces(const std::vector<ForceEdit>& forces, int total, int upres) {
  auto at = [&](int frame) {
    Vec3 sum{0, 0, 0};
    for (const ForceEdit& f : forces)
      if (f.uniform && f.frames.contains(frame)) sum += f.acceleration * static_cast<double>(upres);
    return sum;
  };
  sim::Keyframes<Vec3> keys{{{0.0, at(0)}}};
  for (int t = 1; t < total; ++t) {
    if (at(t) == at(t - 1)) continue;
    if (keys.points.back().first != t - 1) keys.points.emplace_back(t - 1, at(t - 1));
    keys.points.emplace_back(t, at(t));
  }
  return keys;
}

void prepareOut(const fs::path& out, bool overwrite) {
  const std::string name = out.string();
  if (fs::exists(out)) {
    if (!fs::is_directory(out)) throw Error(name + ": exists and is not a folder");
    if (!fs::is_empty(out)) {
      std::ifstream file(out / "run.json");
      const nlohmann::json run = nlohmann::json::parse(file, nullptr, false);
      const bool ours = run.is_object() && run.value("command", "") == "smokesvd resim";
      if (!ours) throw Error(name + ": is not empty and holds no re-simulation; choose another --out (nothing there is touched)");
      if (!overwrite) throw Error(name + ": holds a re-simulation; --overwrite replaces it");
      for (const std::string& f : outputNames()) fs::remove_all(out / f);
    }
  }
  try {
    fs::create_directories(out / "fields");
    fs::create_directories(out / "renders");
  } catch (const fs::filesystem_error& e) {
    throw Error(name + ": cannot create the output folder (" + e.code().message() + ")");
  }
}

std::vector<media::Image> viewFrames(const fs::path& out, int view, int frames) {
  char folder[16];
  std::snprintf(folder, sizeof folder, "view_%02d", view);
  std::vector<media::Image> images;
  for (int t = 0; t < frames; ++t) images.push_back(media::readPng(out / "renders" / folder / (sim::frameName(t) + ".png")));
  return images;
}

// Over the reconstruction's open cells (its walls hold no smoke in a simulation).
FrameDeparture departure(int frame, const std::vector<float>& resim, const std::vector<float>& reconstruction,
                         const std::vector<float>& flags) {
  FrameDeparture d;
  d.frame = frame;
  double difference = 0, norm = 0;
  for (std::size_t i = 0; i < resim.size(); ++i) {
    if (flags[i] == static_cast<float>(physics::kObstacle)) continue;
    const double e = static_cast<double>(resim[i]) - reconstruction[i];
    difference += e * e;
    norm += static_cast<double>(reconstruction[i]) * reconstruction[i];
    d.maxAbs = std::max(d.maxAbs, std::abs(e));
  }
  d.relativeL2 = norm > 0 ? std::sqrt(difference / norm) : std::sqrt(difference);
  return d;
}

}  // namespace

ResimResult runResimulation(Context& context, const ResimOptions& o) {
  const auto began = Clock::now();
  const sim::SavedRun source = sim::readSavedRun(o.source);
  if (source.command != "smokesvd reconstruct")
    throw Error(o.source.string() + ": not a reconstruction (its run.json was written by " + source.command +
                "); resim continues the output of smokesvd reconstruct");
  if (o.upres < 1 || o.upres > 4) throw Error("--upres: expected 1, 2, 3 or 4");
  if (o.frames == 0 || o.frames < -1) throw Error("--frames: expected a frame count >= 1");
  if (!(o.vorticity >= 0)) throw Error("--vorticity: expected a strength >= 0");
  if (!(o.inflowScale >= 0)) throw Error("--inflow-scale: expected a factor >= 0");
  const int total = o.frames > 0 ? o.frames : source.frames;
  const GridSize coarse = source.grid(), grid = finerGrid(coarse, o.upres);

  sim::Scene scene;
  scene.resolution = grid;
  scene.frames = total;
  scene.boundaries = source.scene.boundaries;
  scene.advection = source.scene.advection;
  scene.advectionStrength = source.scene.advectionStrength;
  scene.pressureMaxIterations = 200;
  scene.vorticity = o.vorticity;
  scene.wind = uniformForces(o.forces, total, o.upres);
  scene.windWeighting = sim::WindWeighting::Density;
  scene.render = source.scene.render;
  scene.render.views = 16;
  scene.render.width *= o.upres;
  scene.render.height *= o.upres;
  scene.render.absorption /= o.upres;  // the same optical depth per length of the box
  for (const ObstacleEdit& edit : o.obstacles) scene.obstacles.push_back(obstacleOnGrid(edit, scene, coarse, o.upres, total));
  std::vector<std::vector<float>> fields;  // the force fields' files, read and checked before anything is written
  for (const ForceEdit& edit : o.forces) {
    requireStartsInRun(edit.frames, total, "--force " + edit.text);
    if (edit.uniform) continue;
    fields.push_back(readForceField(edit, coarse));
    sim::ForceField field;
    char name[32];
    std::snprintf(name, sizeof name, "force_%02zu.npz", fields.size() - 1);
    field.file = fs::absolute(o.out / "forces" / name);
    field.frames = edit.frames;
    scene.forceFields.push_back(field);
  }
  ReconstructedDrive drive(context, source, o.upres, o.inflowScale);

  prepareOut(o.out, o.overwrite);
  if (!fields.empty()) fs::create_directories(o.out / "forces");
  for (std::size_t f = 0; f < fields.size(); ++f) {
    const Tensor coarseField = Tensor::fromHost(context, coarse.vector(), fields[f]);
    Stream stream(context);
    const Tensor fine = upsampleCentred(stream, coarseField, o.upres), interleaved(context, {grid.z, grid.y, grid.x, 3});
    physics::planarToInterleaved(stream, fine, interleaved);
    stream.submit();
    io::writeNpz(scene.forceFields[f].file, {{"force", io::NpyArray::fromFloats(interleaved.shape(), interleaved.download())}});
  }
  sim::writeScene(o.out / "scene.json", scene);
  nlohmann::json run{{"command", "smokesvd resim"},
                     {"source", fs::absolute(o.source).string()},
                     {"frames", total},
                     {"reconstructed_frames", source.frames},
                     {"frame_rate", source.frameRate},
                     {"calibration", source.calibration ? nlohmann::json(fs::absolute(*source.calibration).string()) : nlohmann::json()},
                     {"box", {{"grid", {grid.x, grid.y, grid.z}}, {"upres", o.upres}, {"absorption", scene.render.absorption}}},
                     {"options",
                      {{"obstacles", nlohmann::json::array()}, {"forces", nlohmann::json::array()}, {"vorticity", o.vorticity},
                       {"inflow_scale", o.inflowScale}, {"upres", o.upres}}},
                     {"drive", drive.describe()},
                     {"complete", false}};
  for (const ObstacleEdit& e : o.obstacles) run["options"]["obstacles"].push_back(e.text);
  for (const ForceEdit& e : o.forces) run["options"]["forces"].push_back(e.text);
  io::writeJsonFile(o.out / "run.json", run);

  sim::Simulator simulator(context, scene);
  sim::SimulatorState start;
  start.frame = 1;
  start.density = drive.initialDensity();
  start.velocity = drive.initialVelocity();
  start.pressure.assign(static_cast<std::size_t>(grid.cells()), 0.0f);
  simulator.restore(start);
  ResimResult result;
  auto record = [&](int iterations, bool converged) {
    result.maxPressureIterations = std::max(result.maxPressureIterations, iterations);
    result.converged = result.converged && converged;
  };
  const physics::PressureReport first = simulator.enforceDomain();
  record(first.iterations, first.converged);
  const sim::FrameRenderer renderer(scene);
  sim::RunFiles files = sim::RunFiles::unlisted(o.out);  // prepareOut() manages this folder
  const std::vector<float> density0 = simulator.density().download();
  sim::writeFields(o.out, 0, grid, density0, simulator.velocity().download(), density0);
  sim::writeFlags(files, simulator);
  renderer.write(files, simulator);
  const std::vector<float> sourceFlags = sim::sceneFlags(source.scene, 0);
  if (o.upres == 1) result.departures.push_back(departure(0, density0, source.density(0), sourceFlags));

  Progress progress(total, 1, 1, o.quiet);
  nlohmann::json reports = nlohmann::json::array();
  for (int t = 1; t < total; ++t) {
    const StepInputs inputs = drive.next();
    simulator.setExternalInflow(inputs.inflow);
    simulator.setExternalForce(inputs.force);
    const sim::FrameReport report = simulator.advanceFrame();
    record(report.pressureIterations, report.converged);
    reports.push_back({{"frame", t}, {"pressure_iterations", report.pressureIterations},
                       {"max_divergence", report.maxDivergence}, {"converged", report.converged}});
    sim::writeFrameFields(files, simulator);
    renderer.write(files, simulator);
    if (o.upres == 1 && t < source.frames) result.departures.push_back(departure(t, simulator.density().download(), source.density(t), sourceFlags));
    progress.update(t + 1, "frame " + std::to_string(t));
  }
  progress.finish();

  if (o.videos) {
    if (media::findFfmpeg()) {
      media::writeVideo(o.out / "front.mp4", viewFrames(o.out, 0, total), source.frameRate);
      media::writeVideo(o.out / "side.mp4", viewFrames(o.out, 8, total), source.frameRate);
      run["videos"] = {"front.mp4 (view 0, the input camera)", "side.mp4 (view 8)"};
    } else {
      run["videos"] = "skipped: ffmpeg not found";
    }
  }
  result.frames = total;
  result.seconds = std::chrono::duration<double>(Clock::now() - began).count();
  nlohmann::json departures = nlohmann::json::array();
  for (const FrameDeparture& d : result.departures)
    departures.push_back({{"frame", d.frame}, {"relative_l2", d.relativeL2}, {"max_abs", d.maxAbs}});
  if (o.upres == 1) run["departure_from_reconstruction"] = departures;
  run["drive"] = drive.describe();
  run["frame_reports"] = reports;
  run["converged"] = result.converged;
  run["seconds"] = result.seconds;
  run["complete"] = true;
  io::writeJsonFile(o.out / "run.json", run);
  return result;
}

}  // namespace smokesvd::resim
