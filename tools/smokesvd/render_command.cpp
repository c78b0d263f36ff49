// `smokesvd render`: renders density volumes to PNG (and mp4), or checks a camera calibration on real footage.
//
//   smokesvd render density_*.npz --out renders/                      16 orbit views (preset paper sizes)
//   smokesvd render d.npy --angles 0,90 --width 128 --height 224 --out r/
//   smokesvd render d.npy --turntable 72 --mp4 --out r/                one turn, also as r/d_turntable.mp4
//   smokesvd render d.npz --cameras info.json --out r/                 through every calibrated camera
//   smokesvd render --cameras info.json --overlay-frame 90 --out check.png
//        each camera's frame 90 with the projected volume box (and the box, or a given volume, rendered in blue)
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>

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
#include "tools/smokesvd/option_checks.h"

namespace smokesvd::cli {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxViews = 3600;
// Pixels of all the images one volume renders to (and, with --mp4, of all volumes): 1 GiB of floats.
constexpr int64_t kMaxPixels = int64_t{1} << 28;

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

int64_t pixels(const std::vector<LabelledCamera>& cameras) {
  int64_t total = 0;
  for (const LabelledCamera& c : cameras) total += int64_t{c.camera.width} * c.camera.height;
  return total;
}

void checkPixels(int64_t total, const std::string& what) {
  if (total > kMaxPixels)
    throw Error("render: " + what + " come to " + std::to_string(total) + " pixels, more than the " +
                std::to_string(kMaxPixels) + " one render may hold; use fewer views or smaller images");
}

// Output names are the volumes' stems: two volumes of one stem would write each other's files.
void refuseSameStems(const std::vector<std::string>& volumes) {
  std::map<std::string, std::string> byStem;
  for (const std::string& file : volumes) {
    const auto [it, added] = byStem.emplace(fs::path(file).stem().string(), file);
    if (!added)
      throw Error("render: " + it->second + " and " + file + " would both write " + it->first +
                  "_*.png; render them into separate --out folders (or rename one)");
  }
}

void writeVideoOrFail(const fs::path& path, const std::vector<media::Image>& frames, double fps) {
  media::writeVideo(path, frames, fps);
  std::cout << "wrote " << path.string() << "\n";
}

void renderVolumes(const GlobalOptions& global, const RenderArguments& a) {
  if (a.volumes.empty()) throw Error("render: give one or more volume files (.npy or .npz), or --overlay-frame");
  if (a.out.empty()) throw Error("render: --out FOLDER is required");
  refuseSameStems(a.volumes);
  if (a.mp4) media::requireFfmpeg("render --mp4");
  const Preset& preset = smokesvd::preset(a.preset);
  const render::RenderSettings settings = settingsFrom(a);
  fs::create_directories(a.out);
  Context context(global.contextOptions());
  std::vector<std::vector<media::Image>> perVolume;
  std::vector<std::string> labels;
  for (const std::string& file : a.volumes) {
    const media::DensityVolume density = media::readDensityVolume(file, a.key);
    const std::vector<LabelledCamera> labelled = camerasFor(a, preset, density.grid);
    checkPixels(pixels(labelled), file + ": its " + std::to_string(labelled.size()) + " views");
    if (a.mp4 && a.turntable == 0)
      checkPixels(pixels(labelled) * static_cast<int64_t>(a.volumes.size()),
                  "the views of all " + std::to_string(a.volumes.size()) + " volumes (kept for the videos)");
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
    if (a.mp4 && a.turntable == 0) perVolume.push_back(std::move(images));
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
  const auto whole = [](double side) { return side >= 1 && side <= kMaxGridSide && side == std::trunc(side); };
  if (g.size() != 3 || !whole(g[0]) || !whole(g[1]) || !whole(g[2]))
    throw Error("--grid: expected D,H,W, three whole numbers from 1 to " + std::to_string(kMaxGridSide) + ", got '" +
                a.grid + "'");
  const GridSize grid{.x = static_cast<int64_t>(g[2]), .y = static_cast<int64_t>(g[1]), .z = static_cast<int64_t>(g[0])};
  checkGridSize(grid, "--grid");
  return grid;
}

void calibrationOverlay(const GlobalOptions& global, const RenderArguments& a) {
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
  const int width = a.width > 0 ? a.width : 270;
  int64_t total = 0;
  for (const CalibratedView& view : calibration.views)
    total += 2 * int64_t{width} * (int64_t{width} * view.height / std::max(view.width, 1) + 1);  // frame and render
  checkPixels(total, "the frames and renders of " + std::to_string(calibration.views.size()) + " cameras");
  const std::vector<render::ViewCheck> checks = render::checkCalibration(
      calibration, fs::path(a.cameras).parent_path(), a.overlayFrame, width, density.grid);
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
  c->add_option("--width", args.width, "image width in pixels")->check(wholeNumber(1, kMaxImageSide));
  CLI::Option* height = c->add_option("--height", args.height, "orbit image height in pixels")
                            ->check(wholeNumber(1, kMaxImageSide));
  CLI::Option* views = c->add_option("--views", args.views, "orbit views evenly on [0, 180) degrees")
                           ->check(wholeNumber(1, kMaxViews));
  CLI::Option* angles = c->add_option("--angles", args.angles, "orbit angles in degrees, comma-separated");
  CLI::Option* turntable = c->add_option("--turntable", args.turntable, "N orbit views over a full turn")
                               ->check(wholeNumber(1, kMaxViews));
  CLI::Option* cameras = c->add_option("--cameras", args.cameras, "NeRF-style calibration JSON (e.g. ScalarFlow info.json)");
  c->add_option("--camera", args.cameraNames, "render only this calibrated view (file_name), repeatable")->needs(cameras);
  c->add_option("--key", args.key, "array name inside .npz volumes");
  c->add_option("--step", args.step, "march step in voxels")->check(number(0.01, 100));
  c->add_option("--absorption", args.absorption, "extinction per unit density per voxel")->check(number(0, 1e6));
  c->add_option("--ambient", args.ambient, "source radiance without the light")->check(number(0, 1e6));
  CLI::Option* light = c->add_option("--light", args.light, "x,y,z: direction toward a directional light (grid axes, y up)");
  c->add_option("--light-intensity", args.lightIntensity, "light intensity")->check(number(0, 1e6))->needs(light);
  c->add_option("--light-step", args.lightStep, "light march step in voxels")->check(number(0.01, 100))->needs(light);
  c->add_option("--light-absorption", args.lightAbsorption, "extinction along light paths")
      ->check(number(0, 1e6))
      ->needs(light);
  c->add_option("--bits", args.bits, "PNG bits per sample")->check(CLI::IsMember({8, 16}));
  c->add_option("--gain", args.gain, "multiply images by this before writing")->check(number(0, 1e6));
  CLI::Option* mp4 = c->add_flag("--mp4", args.mp4, "also write mp4 videos (needs ffmpeg): one per view over the "
                                                    "volumes, or one per volume with --turntable");
  c->add_option("--fps", args.fps, "mp4 frame rate")->check(positiveNumber(1000))->needs(mp4);
  CLI::Option* overlay = c->add_option("--overlay-frame", args.overlayFrame, "calibration check: draw the projected "
                                                                             "box on this frame of every calibrated video")
                             ->check(wholeNumber(0, 100000000))
                             ->needs(cameras)
                             ->excludes(mp4);
  c->add_option("--grid", args.grid, "D,H,W of the box for --overlay-frame without a volume")->needs(overlay);
  // One way to choose the cameras: calibrated, a turntable, angles or a number of orbit views.
  for (CLI::Option* option : {views, angles, turntable, cameras})
    for (CLI::Option* other : {views, angles, turntable, cameras})
      if (option != other) option->excludes(other);
  height->excludes(cameras);  // calibrated cameras keep their aspect: --width alone sets their size
  overlay->excludes(views)->excludes(angles)->excludes(turntable);
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
