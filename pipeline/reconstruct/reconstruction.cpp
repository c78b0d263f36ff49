#include "pipeline/reconstruct/reconstruction.h"

#include <chrono>
#include <optional>

#include "nets/io/file_io.h"
#include "nets/io/json_file.h"
#include "nets/io/npy.h"
#include "pipeline/media/image.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/progress.h"
#include "pipeline/render/view_set.h"
#include "pipeline/reconstruct/run_outputs.h"
#include "pipeline/sim/domain.h"
#include "pipeline/sim/outputs.h"
#include "pipeline/sim/scene.h"
#include "runtime/error.h"
#include "runtime/stream.h"

namespace smokesvd::reconstruct {
namespace fs = std::filesystem;
namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

nlohmann::json readJson(const fs::path& path) { return io::readJsonFile(path, "delete it or use --overwrite"); }

// What must agree for a run to be resumed: the input, its frames and mapping, the models, every option.
nlohmann::json signature(const ReconstructOptions& o, const MethodModels& models, const FrontViews& views) {
  const InputOptions& in = o.input;
  return {{"input", fs::absolute(in.input).string()},
          {"frames", {in.first, in.count}},
          {"framing", in.framing == Framing::Box ? "box" : in.framing == Framing::Auto ? "auto" : "calibrated"},
          {"calibration", in.calibration.string()},
          {"camera", in.camera},
          {"intensity", in.intensity},
          {"background", in.background == Background::First ? "first" : "level"},
          {"target", in.target},
          {"threshold", in.threshold},
          {"orthographic", in.orthographic},
          {"preset", o.preset},
          {"models", models.hashes},
          {"side_view",
           {{"synthesize", o.sideView.synthesize && o.sideViews.empty()},
            {"given", o.sideViews.empty() ? "" : fs::absolute(o.sideViews).string()},
            {"steps", o.sideView.steps}, {"init_steps", o.sideView.initSteps},
            {"eta", o.sideView.eta}, {"start", o.sideView.start}, {"seed", o.sideView.seed},
            {"samples", o.sideView.samples}, {"init_share", o.sideView.initShare}}},
          {"density", {{"refine", o.density.refine}, {"progressive", o.density.progressive}}},
          {"motion",
           {{"inflow_iterations", o.motion.inflowIterations}, {"inflow_lr", o.motion.inflowLr},
            {"inflow_height", o.motion.inflowHeight}, {"image_weight", o.motion.imageWeight},
            {"smooth_weight", o.motion.smoothWeight}}},
          {"polish",
           {{"steps", o.polish.steps}, {"lr", o.polish.lr}, {"input_weight", o.polish.inputWeight},
            {"view_weight", o.polish.viewWeight}, {"divergence_weight", o.polish.divergenceWeight},
            {"prior_weight", o.polish.priorWeight}}},
          {"source", views.describe()}};
}

// The side views of --side-views from the input's first frame on, one per front view (a longer clip is
// cut to the input's length), or none.
std::optional<FrontViews> readGivenSideViews(const ReconstructOptions& o, const Preset& preset, int frames) {
  if (o.sideViews.empty()) return std::nullopt;
  InputOptions given = o.input;
  given.input = o.sideViews;
  given.framing = Framing::Box;
  given.calibration.clear();
  given.camera.clear();
  given.count = -1;
  FrontViews sides = readFrontViews(given, preset);
  if (static_cast<int>(sides.frames.size()) < frames)
    throw Error(o.sideViews.string() + ": " + std::to_string(sides.frames.size()) + " side views for " +
                std::to_string(frames) + " front views; expected one side view per frame");
  sides.frames.resize(static_cast<std::size_t>(frames));
  return sides;
}

}  // namespace

ReconstructResult runReconstruction(Context& context, const ReconstructOptions& o) {
  const Preset& preset = smokesvd::preset(o.preset);
  if (o.resume && o.overwrite) throw Error("reconstruct: --resume and --overwrite contradict each other");
  const FrontViews views = readFrontViews(o.input, preset);
  const int frames = static_cast<int>(views.frames.size());
  const fs::path modelsFolder = o.models.empty() ? defaultModelsFolder(o.preset) : o.models;
  const std::optional<FrontViews> givenSides = readGivenSideViews(o, preset, frames);
  MethodModels models(context, modelsFolder, preset, o.sideView.synthesize && !givenSides);
  const nlohmann::json runSignature = signature(o, models, views);

  RunFolder folder(o.out);
  const fs::path runPath = o.out / "run.json", checkpointPath = o.out / "checkpoint.npz";
  FrameState state(context, preset);
  ReconstructResult result;
  result.frames = frames;
  double secondsBefore = 0;
  if (fs::exists(runPath)) {
    const nlohmann::json previous = readJson(runPath);
    if (previous.value("command", "") != "smokesvd reconstruct")
      throw Error(runPath.string() + ": not a reconstruction's run.json; choose another --out");
    if (o.overwrite) {
      folder.clear();
    } else {
      if (!o.resume) throw Error(o.out.string() + ": holds a reconstruction; --resume continues it, --overwrite replaces it");
      if (previous.value("signature", nlohmann::json{}) != runSignature)
        throw Error(o.out.string() + ": holds a reconstruction of another input, models or options; --overwrite replaces it");
      if (previous.value("complete", false)) {
        result.complete = true;
        result.seconds = previous.value("seconds_total", 0.0);
        return result;
      }
      if (fs::exists(checkpointPath)) {
        std::map<std::string, io::NpyArray> arrays;
        try {
          arrays = io::readNpz(checkpointPath);
        } catch (const Error& e) {
          throw Error(std::string(e.what()) + " (the checkpoint is damaged: delete " + checkpointPath.string() +
                      " to restart the run, or use --overwrite)");
        }
        state.fromArrays(arrays, checkpointPath.string());
        secondsBefore = previous.value("seconds_total", 0.0);
        const nlohmann::json stages = previous.value("stage_seconds", nlohmann::json::object());
        for (const auto& [stage, seconds] : stages.items()) result.stageSeconds[stage] = seconds.get<double>();
      }
    }
  } else {
    folder.requireEmptyOrAbsent();
  }
  folder.prepare();
  folder.removeTemporaries();

  sim::Scene box;
  box.resolution = preset.grid;
  box.frames = frames;
  box.render.width = preset.imageWidth;
  box.render.height = preset.imageHeight;
  box.render.absorption = preset.absorption;
  box.render.ambient = 1;
  sim::writeScene(o.out / "scene.json", box);
  const Tensor flagsTensor = Tensor::fromHost(context, preset.grid.volume(), sim::sceneFlags(box, 0));
  folder.writeFlags(sim::sceneFlags(box, 0), preset.grid);
  render::RenderSettings look;
  look.absorption = preset.absorption;
  physics::AdvectionParams advection;

  nlohmann::json run{{"command", "smokesvd reconstruct"},
                     {"signature", runSignature},
                     {"preset", o.preset},
                     {"models_folder", fs::absolute(modelsFolder).string()},
                     {"device", context.info().name},
                     {"frames", frames},
                     {"box",
                      {{"grid", {preset.grid.x, preset.grid.y, preset.grid.z}},
                       {"units", "densities in the preset's reference absorption: render with absorption " +
                                     std::to_string(preset.absorption) + ", ambient 1, no light"},
                       {"absorption", preset.absorption}}}};
  auto saveRun = [&](bool complete, double seconds) {
    run["complete"] = complete;
    run["frames_done"] = state.framesDone;
    run["seconds_total"] = seconds;
    run["seconds_per_frame"] = state.framesDone > 0 ? seconds / state.framesDone : 0.0;
    run["stage_seconds"] = result.stageSeconds;
    io::writeJsonFile(runPath, run);
  };
  if (state.framesDone == 0) saveRun(false, 0);

  const auto began = Clock::now();
  Progress progress(frames, state.framesDone, 1, o.quiet);
  auto imageTensor = [&](const std::vector<std::vector<float>>& images, int t) {
    return Tensor::fromHost(context, {1, 1, preset.imageHeight, preset.imageWidth}, images[static_cast<std::size_t>(t)]);
  };
  // The input's own camera (motion_stage.h), and the polish's cameras: that camera at slot 0, the orbit slots else.
  const render::ViewSet inputView = render::uploadViews(context, std::vector<Camera>{views.inputCamera});
  const render::ViewSet polishViews = [&] {
    std::vector<Camera> cameras = networks::slotCameras(preset);
    cameras[networks::kFrontSlot] = views.inputCamera;
    return render::uploadViews(context, cameras);
  }();
  const physics::FlagGrid grid = [&] {
    Stream stream(context);
    physics::FlagGrid g(stream, flagsTensor);
    stream.submit();
    return g;
  }();
  std::vector<std::string> stageOrder;
  for (int t = state.framesDone; t < frames; ++t) {
    if (o.stopAfter >= 0 && result.framesThisCall >= o.stopAfter) break;
    const Tensor front = imageTensor(views.frames, t);
    const Tensor nextFront = imageTensor(views.frames, std::min(t + 1, frames - 1));
    const Tensor input = imageTensor(views.inputFrames, t);
    auto timed = [&](const char* stage, auto&& work) {
      if (result.framesThisCall == 0) stageOrder.push_back(stage);
      const auto start = Clock::now();
      auto value = work();
      result.stageSeconds[stage] += since(start);
      return value;
    };
    const Tensor side = timed("side_view", [&] {
      return givenSides ? Tensor::fromHost(context, front.shape(), givenSides->frames[static_cast<std::size_t>(t)])
                        : sideView(context, models, state, t, front, nextFront, o.sideView);
    });
    const DensityResult density = timed("density", [&] {
      return reconstructDensity(context, models, state, t, front, side, look, o.density);
    });
    MotionResult motion = timed("motion", [&] {
      return advanceDensity(context, models, state, t, grid, density.density, input, inputView, look, advection, o.motion);
    });
    if (o.polish.steps > 0)
      timed("polish", [&] {
        polishMotion(context, state, t, grid, polishViews, density.views, input, look, advection, o.motion, o.polish, motion);
        return 0;
      });
    timed("write", [&] {
      folder.writeFrame(t, motion.density, motion.inflow, density.views, side, input);
      if (motion.velocity.defined()) folder.writeVelocity(t - 1, motion.velocity);
      if (t == frames - 1) folder.writeVelocity(t, motion.velocity.defined() ? motion.velocity : Tensor());
      Stream stream(context);
      state.advance(stream, side, density.sideRender, density.views, motion.density, motion.inflow);
      stream.submit();
      state.framesDone = t + 1;
      io::writeNpz(checkpointPath, state.toArrays());
      saveRun(false, secondsBefore + since(began));
      return 0;
    });
    if (result.framesThisCall == 0) {
      run["stage_order"] = stageOrder;
      saveRun(false, secondsBefore + since(began));
    }
    ++result.framesThisCall;
    progress.update(t + 1, "frame " + std::to_string(t));
  }
  progress.finish();
  result.seconds = secondsBefore + since(began);
  if (state.framesDone < frames) return result;

  if (o.videos) {
    const auto start = Clock::now();
    run["videos"] = folder.writeSummaries(context, frames, views.frameRate, look, preset);
    result.stageSeconds["summaries"] += since(start);
  }
  fs::remove(checkpointPath);
  result.complete = true;
  result.seconds = secondsBefore + since(began);
  saveRun(true, result.seconds);
  return result;
}

}  // namespace smokesvd::reconstruct
