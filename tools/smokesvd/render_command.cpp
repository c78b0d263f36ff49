// `smokesvd render`: renders density volumes to PNG (and mp4), or checks a camera calibration on real footage.
//
//   smokesvd render density_*.npz --out renders/                      16 orbit views (preset paper sizes)
//   smokesvd render d.npy --angles 0,90 --width 128 --height 224 --out r/
//   smokesvd render d.npy --turntable 72 --mp4 --out r/                one turn, also as r/d_turntable.mp4
//   smokesvd render d.npz --cameras info.json --out r/                 through every calibrated camera
//   smokesvd render --cameras info.json --overlay-frame 90 --out check.png
//        each camera's frame 90 with the projected volume box (and the box, or a given volume, rendered in blue)
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "nets/op_registry.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/media/image.h"
#include "pipeline/media/video.h"
#include "pipeline/media/volume_file.h"
#include "pipeline/preset.h"
#include "pipeline/render/calibration_check.h"
#include "pipeline/render/render_images.h"
#include "runtime/error.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

namespace fs = std::filesystem;

struct RenderArguments {
  std::vector<std::string> volumes;
  std::string out;
  std::string preset = "paper";
  int width = 0, height = 0, views = 0, turntable = 0;
  std::string angles, cameras, key, grid;
  std::vector<std::string> cameraNames;
  float step = 1, absorption = 1, ambient = 1;
  std::string light;
  float lightIntensity = 1, lightStep = 1, lightAbsorption = 1;
  int bits = 8;
  float gain = 1;
  bool mp4 = false;
  double fps = 30;
  int overlayFrame = -1;
};

struct LabelledCamera {
  std::string label;
  Camera camera;
};

render::RenderSettings settingsFrom(const RenderArguments& a) {
  render::RenderSettings s;
  s.step = a.step;
  s.absorption = a.absorption;
  s.ambient = a.ambient;
  if (!a.light.empty()) {
    const std::vector<double> d = parseNumberList(a.light, "--light");
    if (d.size() != 3) throw Error("--light: expected three numbers x,y,z (direction toward the light)");
    s.light = render::DirectionalLight{{d[0], d[1], d[2]}, a.lightIntensity, a.lightStep, a.lightAbsorption};
  }
  render::validate(s);
  return s;
}

std::string angleLabel(const char* prefix, double angle) {
  char text[32];
  std::snprintf(text, sizeof text, "%s%05.1f", prefix, angle);
  return text;
}

std::vector<LabelledCamera> camerasFor(const RenderArguments& a, const Preset& preset, const GridSize& grid) {
  std::vector<LabelledCamera> cameras;
  if (!a.cameras.empty()) {
    const Calibration calibration = readCalibration(a.cameras);
    std::vector<CalibratedView> views;
    if (a.cameraNames.empty()) views = calibration.views;
    for (const std::string& name : a.cameraNames) views.push_back(calibration.view(name));
    for (const CalibratedView& view : views)
      cameras.push_back({fs::path(view.fileName).stem().string(),
                         calibratedCamera(view, calibration.box, grid, a.width > 0 ? a.width : view.width / 4)});
    return cameras;
  }
  const int width = a.width > 0 ? a.width : preset.imageWidth, height = a.height > 0 ? a.height : preset.imageHeight;
  if (a.turntable > 0) {
    for (int i = 0; i < a.turntable; ++i) {
      char label[32];
      std::snprintf(label, sizeof label, "t%03d", i);
      cameras.push_back({label, orbitCamera(360.0 * i / a.turntable, grid, width, height)});
    }
    return cameras;
  }
  const std::vector<double> angles = a.angles.empty() ? orbitAngles(a.views > 0 ? a.views : preset.views)
                                                      : parseNumberList(a.angles, "--angles");
  for (double angle : angles) cameras.push_back({angleLabel("a", angle), orbitCamera(angle, grid, width, height)});
  return cameras;
}

void writeVideoOrFail(const fs::path& path, const std::vector<media::Image>& frames, double fps) {
  media::writeVideo(path, frames, fps);
  std::cout << "wrote " << path.string() << "\n";
}

void renderVolumes(const GlobalOptions& global, const RenderArguments& a) {
  if (a.volumes.empty()) throw Error("render: give one or more volume files (.npy or .npz), or --overlay-frame");
  if (a.out.empty()) throw Error("render: --out FOLDER is required");
  if (a.mp4 && !media::findFfmpeg()) throw Error("render --mp4: ffmpeg was not found (install it or set SMOKESVD_FFMPEG)");
  const Preset& preset = smokesvd::preset(a.preset);
  const render::RenderSettings settings = settingsFrom(a);
  fs::create_directories(a.out);
  Context context(global.contextOptions());
  std::vector<std::vector<media::Image>> perVolume;
  std::vector<std::string> labels;
  for (const std::string& file : a.volumes) {
    const media::DensityVolume density = media::readDensityVolume(file, a.key);
    const std::vector<LabelledCamera> labelled = camerasFor(a, preset, density.grid);
    std::vector<Camera> cameras;
    labels.clear();
    for (const LabelledCamera& c : labelled) {
      cameras.push_back(c.camera);
      labels.push_back(c.label);
    }
    const Tensor volume = Tensor::fromHost(context, density.grid.volume(), density.values);
    std::vector<media::Image> images = render::renderImages(context, volume, cameras, settings, a.gain);
    const std::string stem = fs::path(file).stem().string();
    for (std::size_t v = 0; v < images.size(); ++v)
      media::writePng(fs::path(a.out) / (stem + "_" + labels[v] + ".png"), images[v], a.bits);
    std::cout << file << ": " << images.size() << " views, grid " << density.grid.z << "x" << density.grid.y
              << "x" << density.grid.x << " -> " << a.out << "/" << stem << "_*.png\n";
    if (a.mp4 && a.turntable > 0) writeVideoOrFail(fs::path(a.out) / (stem + "_turntable.mp4"), images, a.fps);
    perVolume.push_back(std::move(images));
  }
  if (a.mp4 && a.turntable == 0) {
    for (std::size_t v = 0; v < labels.size(); ++v) {
      std::vector<media::Image> frames;
      for (const auto& images : perVolume) frames.push_back(images[v]);
      writeVideoOrFail(fs::path(a.out) / (labels[v] + ".mp4"), frames, a.fps);
    }
  }
}

GridSize overlayGrid(const RenderArguments& a, const Preset& preset) {
  if (a.grid.empty()) return preset.grid;
  const std::vector<double> g = parseNumberList(a.grid, "--grid");
  if (g.size() != 3 || g[0] < 1 || g[1] < 1 || g[2] < 1) throw Error("--grid: expected D,H,W (three positive sizes)");
  return {.x = static_cast<int64_t>(g[2]), .y = static_cast<int64_t>(g[1]), .z = static_cast<int64_t>(g[0])};
}

void calibrationOverlay(const GlobalOptions& global, const RenderArguments& a) {
  if (a.cameras.empty()) throw Error("render --overlay-frame: needs --cameras info.json");
  if (a.out.empty() || fs::path(a.out).extension() != ".png") throw Error("render --overlay-frame: --out FILE.png");
  if (a.volumes.size() > 1) throw Error("render --overlay-frame: give at most one volume");
  const Calibration calibration = readCalibration(a.cameras);
  media::DensityVolume density;
  if (a.volumes.empty()) {
    density.grid = overlayGrid(a, smokesvd::preset(a.preset));
    density.values.assign(static_cast<std::size_t>(density.grid.cells()), 1.0f);
  } else {
    density = media::readDensityVolume(a.volumes[0], a.key);
  }
  const std::vector<render::ViewCheck> checks = render::checkCalibration(
      calibration, fs::path(a.cameras).parent_path(), a.overlayFrame, a.width > 0 ? a.width : 270, density.grid);
  std::vector<Camera> cameras;
  for (const render::ViewCheck& check : checks) cameras.push_back(check.camera);
  render::RenderSettings settings = settingsFrom(a);
  Context context(global.contextOptions());
  const Tensor volume = Tensor::fromHost(context, density.grid.volume(), density.values);
  const std::vector<media::Image> renders = render::renderImages(context, volume, cameras, settings, a.gain);
  std::vector<media::Image> tiles;
  for (std::size_t i = 0; i < checks.size(); ++i) {
    tiles.push_back(render::overlayTile(checks[i].frame, renders[i], checks[i].camera, density.grid));
    std::printf("%s: box centre at pixel (%.1f, %.1f) of %dx%d, %s the frame; frame value there %.3f (frame mean %.3f)\n",
                checks[i].fileName.c_str(), checks[i].centre[0], checks[i].centre[1], checks[i].camera.width,
                checks[i].camera.height, checks[i].centreInFrame ? "inside" : "OUTSIDE",
                static_cast<double>(checks[i].brightnessAtCentre), static_cast<double>(checks[i].frameMean));
  }
  media::writePng(a.out, render::besideEachOther(tiles), 8);
  std::cout << "wrote " << a.out << "\n";
}

void addRenderCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  static RenderArguments args;
  CLI::App* c = app.add_subcommand("render", "render density volumes to PNG/mp4, or check a camera calibration");
  c->add_option("volumes", args.volumes, ".npy/.npz density volumes [z,y,x] (ScalarFlow 'data' and mantaflow "
                                         "'arr_0' [z,y,x,1] accepted)");
  c->add_option("--out", args.out, "output folder (or the .png file with --overlay-frame)");
  c->add_option("--preset", args.preset, "tiny, small or paper: default image size and view count");
  c->add_option("--width", args.width, "image width in pixels")->check(CLI::PositiveNumber);
  c->add_option("--height", args.height, "orbit image height in pixels")->check(CLI::PositiveNumber);
  c->add_option("--views", args.views, "orbit views evenly on [0, 180) degrees")->check(CLI::PositiveNumber);
  c->add_option("--angles", args.angles, "orbit angles in degrees, comma-separated");
  c->add_option("--turntable", args.turntable, "N orbit views over a full turn")->check(CLI::PositiveNumber);
  c->add_option("--cameras", args.cameras, "NeRF-style calibration JSON (e.g. ScalarFlow info.json)");
  c->add_option("--camera", args.cameraNames, "render only this calibrated view (file_name), repeatable");
  c->add_option("--key", args.key, "array name inside .npz volumes");
  c->add_option("--step", args.step, "march step in voxels");
  c->add_option("--absorption", args.absorption, "extinction per unit density per voxel");
  c->add_option("--ambient", args.ambient, "source radiance without the light");
  c->add_option("--light", args.light, "x,y,z: direction toward a directional light (grid axes, y up)");
  c->add_option("--light-intensity", args.lightIntensity, "light intensity");
  c->add_option("--light-step", args.lightStep, "light march step in voxels");
  c->add_option("--light-absorption", args.lightAbsorption, "extinction along light paths");
  c->add_option("--bits", args.bits, "PNG bits per sample")->check(CLI::IsMember({8, 16}));
  c->add_option("--gain", args.gain, "multiply images by this before writing");
  c->add_flag("--mp4", args.mp4, "also write mp4 videos (needs ffmpeg): one per view over the volumes, or "
                                 "one per volume with --turntable");
  c->add_option("--fps", args.fps, "mp4 frame rate")->check(CLI::PositiveNumber);
  c->add_option("--overlay-frame", args.overlayFrame, "calibration check: draw the projected box on this frame of "
                                                      "every calibrated video")->check(CLI::NonNegativeNumber);
  c->add_option("--grid", args.grid, "D,H,W of the box for --overlay-frame without a volume");
  c->callback([&global, &action] {
    action = [&global] {
      if (args.overlayFrame >= 0) calibrationOverlay(global, args);
      else renderVolumes(global, args);
    };
  });
}

const bool registered = registerCommand({"render", addRenderCommand});

}  // namespace
}  // namespace smokesvd::cli
