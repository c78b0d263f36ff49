#include "pipeline/eval/footage_references.h"

#include <algorithm>
#include <cmath>

#include "pipeline/media/video.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/preset.h"
#include "runtime/error.h"

namespace smokesvd::eval {
namespace fs = std::filesystem;
namespace {

constexpr int kChunk = 8;  // video frames decoded at a time

bool selectedCamera(const std::vector<std::string>& selected, const std::string& fileName) {
  if (selected.empty()) return true;
  const std::string stem = fs::path(fileName).stem().string();
  return std::find(selected.begin(), selected.end(), fileName) != selected.end() ||
         std::find(selected.begin(), selected.end(), stem) != selected.end();
}

nlohmann::json regionJson(const reconstruct::Region& r) {
  return {{"x0", r.x0}, {"y0", r.y0}, {"width", r.width}, {"height", r.height}};
}

}  // namespace

Region parseRegion(const std::string& text) {
  if (text == "box") return Region::Box;
  if (text == "frame") return Region::Frame;
  throw Error("--region: expected box or frame, got '" + text + "'");
}

FootageReferences::FootageReferences(const ReconstructionRun& run, const FootageOptions& options)
    : run_(run), options_(options) {
  if (options.supersample < 1) throw Error("--supersample: expected at least 1");
  if (options.region == Region::Frame && options.width < kSsimWindow)
    throw Error("--width: expected at least " + std::to_string(kSsimWindow) + " pixels");
  const Calibration calibration = readCalibration(options.calibration);
  if (run.framing != reconstruct::Framing::Calibrated)
    throw Error(run.folder.string() + ": evaluating against calibrated cameras needs a reconstruction made with --camera "
                "info.json (its box placed by the calibration); this one was framed '" +
                std::string(run.framing == reconstruct::Framing::Box ? "box" : "auto") + "'");
  auto requireView = [&](const std::string& name, const std::string& role) {
    const bool known = std::any_of(calibration.views.begin(), calibration.views.end(), [&](const CalibratedView& v) {
      return v.fileName == name || fs::path(v.fileName).stem().string() == name;
    });
    if (known) return;
    std::string names;
    for (const CalibratedView& v : calibration.views) names += (names.empty() ? "" : ", ") + v.fileName;
    throw Error(options.calibration.string() + ": no camera '" + name + "' (" + role + "); it has " + names);
  };
  requireView(run.camera, "the reconstruction's input");
  for (const std::string& name : options.selected) requireView(name, "--views");
  const Preset& preset = smokesvd::preset(run.preset);
  const double aspect = static_cast<double>(preset.imageWidth) / preset.imageHeight;
  for (const CalibratedView& calibrated : calibration.views) {
    const bool input = calibrated.fileName == run.camera;
    if (!input && !selectedCamera(options.selected, calibrated.fileName)) continue;
    Footage footage;
    footage.video = options.videos / calibrated.fileName;
    if (!fs::exists(footage.video))
      throw Error(footage.video.string() + ": no such video (--videos must hold the video of every camera of " +
                  options.calibration.filename().string() + ")");
    const media::VideoInfo info = media::probeVideo(footage.video);
    if (info.frameCount > 0 && info.frameCount < run.firstFrame + run.frames)
      throw Error(footage.video.string() + ": " + std::to_string(info.frameCount) + " frames, the reconstruction covers frames " +
                  std::to_string(run.firstFrame) + " to " + std::to_string(run.firstFrame + run.frames - 1));
    if (std::abs(static_cast<double>(calibrated.width) / calibrated.height - static_cast<double>(info.width) / info.height) > 0.01)
      throw Error(options.calibration.string() + ": camera '" + calibrated.fileName + "' is " + std::to_string(calibrated.width) +
                  "x" + std::to_string(calibrated.height) + ", its video " + std::to_string(info.width) + "x" +
                  std::to_string(info.height) + " (another aspect ratio)");
    footage.sourceWidth = info.width;
    footage.sourceHeight = info.height;
    const smokesvd::Camera camera = calibratedCamera(calibrated, calibration.box, run.grid, info.width);
    int width = preset.imageWidth, height = preset.imageHeight;
    if (options.region == Region::Box) {
      footage.region = reconstruct::calibratedRegion(camera, run.grid, aspect);
    } else {
      footage.region = {0, 0, static_cast<double>(info.width), static_cast<double>(info.height)};
      width = options.width;
      height = std::max(1, static_cast<int>(std::lround(static_cast<double>(width) * info.height / info.width)));
    }
    if (input && options.region == Region::Box) {
      const reconstruct::Region& r = run.region;
      const double tolerance = 1e-6 * info.width;
      if (info.width != run.sourceWidth || info.height != run.sourceHeight || std::abs(r.x0 - footage.region.x0) > tolerance ||
          std::abs(r.y0 - footage.region.y0) > tolerance || std::abs(r.width - footage.region.width) > tolerance ||
          std::abs(r.height - footage.region.height) > tolerance)
        throw Error(options.calibration.string() + ": the box projects into '" + calibrated.fileName +
                    "' elsewhere than in the reconstruction's input (run.json's signature/source/region); was it made "
                    "with another calibration or video?");
    }
    EvalView view;
    view.name = calibrated.fileName;
    view.group = input ? ViewGroup::Input : ViewGroup::Novel;
    view.camera = windowCamera(camera, footage.region.x0, footage.region.y0, footage.region.width, footage.region.height, width, height);
    view.supersample = options.supersample;
    view.description = {{"camera", "calibrated perspective: " + calibrated.fileName},
                        {"angle_degrees", orbitAngleOf(camera)},
                        {"region", options.region == Region::Box ? "the box's projection, widened to the preset's aspect"
                                                                 : "the whole frame"},
                        {"region_pixels", regionJson(footage.region)},
                        {"source_size", {info.width, info.height}},
                        {"resolution", {width, height}}};
    views_.push_back(view);
    footage_.push_back(std::move(footage));
  }
  // The input camera first, then the others by their angle about the box.
  std::vector<std::size_t> order(views_.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const bool inputA = views_[a].group == ViewGroup::Input, inputB = views_[b].group == ViewGroup::Input;
    if (inputA != inputB) return inputA;
    return views_[a].description["angle_degrees"].get<double>() < views_[b].description["angle_degrees"].get<double>();
  });
  std::vector<EvalView> sortedViews;
  std::vector<Footage> sortedFootage;
  for (std::size_t i : order) {
    sortedViews.push_back(std::move(views_[i]));
    sortedFootage.push_back(std::move(footage_[i]));
  }
  views_ = std::move(sortedViews);
  footage_ = std::move(sortedFootage);
  EvalView side;
  side.name = "side_90";
  side.group = ViewGroup::Side;
  side.camera = networks::orbitCameraAt(preset, 90.0);
  side.hasReference = false;
  side.description = {{"camera", "orbit, orthographic (no camera filmed it)"},
                      {"angle_degrees", 90.0},
                      {"region", "the orbit window: the box's x extent by its y extent, centred on the box"},
                      {"resolution", {preset.imageWidth, preset.imageHeight}}};
  views_.push_back(side);
  footage_.emplace_back();
}

const media::Image& FootageReferences::sourceFrame(Footage& footage, int t) {
  if (footage.chunkStart < 0 || t < footage.chunkStart || t >= footage.chunkStart + static_cast<int>(footage.chunk.size())) {
    const int count = std::min(kChunk, run_.frames - t);
    footage.chunk = media::readVideoFrames(footage.video, run_.firstFrame + t, count);
    footage.chunkStart = t;
    if (static_cast<int>(footage.chunk.size()) < count)
      throw Error(footage.video.string() + ": ends at frame " + std::to_string(run_.firstFrame + t + static_cast<int>(footage.chunk.size())) +
                  ", the reconstruction covers frames up to " + std::to_string(run_.firstFrame + run_.frames - 1));
    const media::Image& first = footage.chunk[0];
    if (first.width != footage.sourceWidth || first.height != footage.sourceHeight)
      throw Error(footage.video.string() + ": frames of " + std::to_string(first.width) + "x" + std::to_string(first.height) +
                  ", expected " + std::to_string(footage.sourceWidth) + "x" + std::to_string(footage.sourceHeight));
  }
  return footage.chunk[static_cast<std::size_t>(t - footage.chunkStart)];
}

std::vector<media::Image> FootageReferences::frame(Context&, int t) {
  std::vector<media::Image> images;
  for (std::size_t v = 0; v < views_.size(); ++v) {
    Footage& footage = footage_[v];
    if (!views_[v].hasReference) {
      images.emplace_back();
      continue;
    }
    const int width = views_[v].camera.width, height = views_[v].camera.height;
    if (run_.mapping.perPixelBackground && footage.background.values.empty()) {
      footage.background = sourceFrame(footage, 0);
      footage.backgroundAtView = media::Image::gray(width, height);
      footage.backgroundAtView.values = reconstruct::resampleRegion(footage.background, footage.region, width, height);
    }
    media::Image source = sourceFrame(footage, t);
    if (options_.units == Units::Mapped)
      mapIntensity(source, run_.mapping, run_.mapping.perPixelBackground ? &footage.background : nullptr);
    media::Image image = media::Image::gray(width, height);
    image.values = reconstruct::resampleRegion(source, footage.region, width, height);
    clampUnit(image);
    images.push_back(std::move(image));
  }
  return images;
}

void FootageReferences::toUnits(std::size_t view, media::Image& render) const {
  if (options_.units == Units::Footage && views_[view].hasReference)
    mapBack(render, run_.mapping, run_.mapping.perPixelBackground ? &footage_[view].backgroundAtView : nullptr);
}

nlohmann::json FootageReferences::describe() const {
  return {{"kind", "footage"},
          {"cameras", fs::absolute(options_.calibration).string()},
          {"videos", fs::absolute(options_.videos).string()},
          {"video_frames", {run_.firstFrame, run_.firstFrame + run_.frames - 1}},
          {"region", options_.region == Region::Box ? "box" : "frame"},
          {"supersample", options_.supersample},
          {"look", {{"absorption", run_.absorption}, {"ambient", 1}, {"light", "none"}}}};
}

}  // namespace smokesvd::eval
