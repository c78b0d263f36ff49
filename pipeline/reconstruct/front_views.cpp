#include "pipeline/reconstruct/front_views.h"

#include <algorithm>
#include <cmath>

#include "nets/io/npy.h"
#include "pipeline/camera/calibration.h"
#include "pipeline/media/video.h"
#include "runtime/error.h"

namespace smokesvd::reconstruct {
namespace fs = std::filesystem;
namespace {

struct Frames {
  std::vector<media::Image> images;
  double frameRate = 30;
};

std::string lowerExtension(const fs::path& path) {
  std::string e = path.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// An .npy / .npz image stack [T, H, W] (or [T, H, W, 3|4], colour to luminance).
Frames readStack(const fs::path& path, int first, int count) {
  io::NpyArray array;
  if (lowerExtension(path) == ".npz") {
    const auto members = io::readNpz(path);
    if (members.count("frames")) array = members.at("frames");
    else if (members.size() == 1) array = members.begin()->second;
    else throw Error(path.string() + ": an .npz image stack needs a member 'frames' (or only one member)");
  } else {
    array = io::readNpy(path);
  }
  const Shape& s = array.shape;
  const bool colour = s.size() == 4 && (s[3] == 3 || s[3] == 4);
  if (!(s.size() == 3 || colour))
    throw Error(path.string() + ": an image stack must be [frames, height, width] (or [..., 3|4] colour), got " + toString(s));
  const std::vector<float> values = array.toFloat();
  const int64_t frames = s[0], height = s[1], width = s[2], channels = colour ? s[3] : 1;
  Frames out;
  for (int64_t t = std::max(first, 0); t < frames && (count < 0 || static_cast<int>(out.images.size()) < count); ++t) {
    media::Image image = media::Image::gray(static_cast<int>(width), static_cast<int>(height));
    for (int64_t i = 0; i < height * width; ++i) {
      const float* v = &values[static_cast<std::size_t>((t * height * width + i) * channels)];
      image.values[static_cast<std::size_t>(i)] = colour ? 0.299f * v[0] + 0.587f * v[1] + 0.114f * v[2] : v[0];
    }
    out.images.push_back(std::move(image));
  }
  return out;
}

Frames readInput(const InputOptions& o) {
  if (!fs::exists(o.input)) throw Error(o.input.string() + ": no such file or folder (expected a video, PNG frames or an .npy/.npz stack)");
  Frames frames;
  const std::string extension = lowerExtension(o.input);
  if (!fs::is_directory(o.input) && (extension == ".npy" || extension == ".npz")) {
    frames = readStack(o.input, o.first, o.count);
  } else {
    if (!fs::is_directory(o.input)) frames.frameRate = media::probeVideo(o.input).frameRate;
    frames.images = media::readFrames(o.input, o.first, o.count);
  }
  if (frames.images.empty())
    throw Error(o.input.string() + ": no frames from frame " + std::to_string(o.first) + " on (--frames out of range?)");
  if (o.count > 0 && static_cast<int>(frames.images.size()) < o.count)
    throw Error(o.input.string() + ": --frames asks for " + std::to_string(o.count) + " frames from " +
                std::to_string(o.first) + ", the input has only " + std::to_string(frames.images.size()) + " there");
  const int w = frames.images[0].width, h = frames.images[0].height;
  for (std::size_t t = 0; t < frames.images.size(); ++t) {
    const media::Image& image = frames.images[t];
    if (image.width != w || image.height != h)
      throw Error(o.input.string() + ": frame " + std::to_string(o.first + static_cast<int>(t)) + " is " +
                  std::to_string(image.width) + "x" + std::to_string(image.height) + ", frame " + std::to_string(o.first) +
                  " is " + std::to_string(w) + "x" + std::to_string(h));
    for (std::size_t i = 0; i < image.values.size(); ++i)
      if (!std::isfinite(image.values[i]))
        throw Error(o.input.string() + ": frame " + std::to_string(o.first + static_cast<int>(t)) + ", pixel (row " +
                    std::to_string(i / static_cast<std::size_t>(w)) + ", column " + std::to_string(i % static_cast<std::size_t>(w)) +
                    ") is not a finite number");
  }
  if (!(frames.frameRate > 0) || !std::isfinite(frames.frameRate)) frames.frameRate = 30;
  return frames;
}

// The q-quantile of up to ~1M values sampled evenly from every frame.
float quantile(const std::vector<media::Image>& frames, double q) {
  std::vector<float> sample;
  const std::size_t total = frames.size() * frames[0].values.size();
  const std::size_t stride = std::max<std::size_t>(1, total / 1000000);
  for (std::size_t i = 0; i < total; i += stride)
    sample.push_back(frames[i / frames[0].values.size()].values[i % frames[0].values.size()]);
  const std::size_t k = std::min(sample.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sample.size())));
  std::nth_element(sample.begin(), sample.begin() + static_cast<std::ptrdiff_t>(k), sample.end());
  return sample[k];
}

IntensityMapping chooseMapping(std::vector<media::Image>& frames, const InputOptions& o) {
  IntensityMapping m;
  if (o.intensity == "none") return m;
  if (o.intensity != "auto") {
    std::size_t used = 0;
    try {
      m.gain = std::stof(o.intensity, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != o.intensity.size() || !(m.gain > 0) || !std::isfinite(m.gain))
      throw Error("--intensity: expected auto, none or a positive gain, got '" + o.intensity + "'");
    return m;
  }
  if (o.background == Background::First) {
    const media::Image background = frames[0];
    for (media::Image& f : frames)
      for (std::size_t i = 0; i < f.values.size(); ++i) f.values[i] -= background.values[i];
    m.perPixelBackground = true;
  } else {
    m.black = quantile(frames, 0.02);
  }
  const float high = quantile(frames, 0.999) - m.black;
  if (!(high > 1e-6f))
    throw Error(o.input.string() + ": no contrast in the footage (its 99.9th percentile equals its black level); "
                "nothing to reconstruct");
  m.gain = o.target / high;
  m.threshold = o.threshold;
  return m;
}

Region fitAspect(double cx, double bottom, double width, double height, double aspect) {
  // aspect = region width / region height
  if (width / height < aspect) width = height * aspect;
  else height = width / aspect;
  return {cx - width / 2, bottom - height, width, height};
}

Region autoRegion(const std::vector<media::Image>& frames, double aspect, const std::string& input) {
  int xmin = INT32_MAX, xmax = -1, ymin = INT32_MAX, ymax = -1;
  for (const media::Image& f : frames)
    for (int r = 0; r < f.height; ++r)
      for (int c = 0; c < f.width; ++c)
        if (f.at(r, c) > 0) {
          xmin = std::min(xmin, c);
          xmax = std::max(xmax, c);
          ymin = std::min(ymin, r);
          ymax = std::max(ymax, r);
        }
  if (xmax < 0)
    throw Error(input + ": no smoke found (every pixel within the threshold of the black level); try --framing box or a "
                "lower --threshold");
  const double smokeWidth = xmax - xmin + 1, smokeHeight = ymax - ymin + 1;
  const double width = std::max(smokeWidth / 0.6, smokeHeight / 0.92 * aspect);
  const double height = width / aspect;
  return fitAspect(0.5 * (xmin + xmax + 1), ymax + 1 + 0.04 * height, width, height, aspect);
}

// The mean of `image` over the rectangle of size w x h centred at (cx, cy) (pixel coordinates; pixels outside
// the image are black), the rectangle widened to at least one source pixel on each side.
float areaMean(const media::Image& image, double cx, double cy, double w, double h) {
  const double fx = std::max(w, 1.0), fy = std::max(h, 1.0);
  auto coverage = [](double a, double b, int n) {  // coverage of source cells [i, i+1) by [a, b)
    std::vector<std::pair<int, double>> cells;
    for (int i = static_cast<int>(std::floor(a)); i < static_cast<int>(std::ceil(b)); ++i) {
      const double overlap = std::min(b, i + 1.0) - std::max(a, static_cast<double>(i));
      if (overlap > 0 && i >= 0 && i < n) cells.emplace_back(i, overlap);
    }
    return cells;
  };
  double sum = 0;
  for (const auto& [y, a] : coverage(cy - fy / 2, cy + fy / 2, image.height))
    for (const auto& [x, b] : coverage(cx - fx / 2, cx + fx / 2, image.width)) sum += a * b * image.at(y, x);
  return static_cast<float>(sum / (fx * fy));
}

}  // namespace

Framing parseFraming(const std::string& text) {
  if (text == "box") return Framing::Box;
  if (text == "auto") return Framing::Auto;
  if (text == "calibrated") return Framing::Calibrated;
  throw Error("--framing: expected box, auto or calibrated, got '" + text + "'");
}

void applyMapping(std::vector<media::Image>& frames, const IntensityMapping& m) {
  for (media::Image& f : frames)
    for (float& v : f.values) v = std::clamp((std::max(0.0f, (v - m.black) * m.gain - m.threshold)) / (1.0f - m.threshold), 0.0f, 1.0f);
}

Region calibratedRegion(const Camera& camera, const GridSize& grid, double aspect) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const Vec3& corner : gridCorners(grid)) {
    const auto p = camera.project(corner);
    if (!p) throw Error("calibration: a corner of the volume box lies behind the input camera");
    x0 = std::min(x0, (*p)[0]);
    x1 = std::max(x1, (*p)[0]);
    y0 = std::min(y0, (*p)[1]);
    y1 = std::max(y1, (*p)[1]);
  }
  return fitAspect(0.5 * (x0 + x1), y1, x1 - x0, y1 - y0, aspect);
}

std::vector<float> resampleRegion(const media::Image& image, const Region& region, int width, int height) {
  const double sx = region.width / width, sy = region.height / height;
  std::vector<float> out(static_cast<std::size_t>(width * height), 0.0f);
  for (int r = 0; r < height; ++r)
    for (int c = 0; c < width; ++c)
      out[static_cast<std::size_t>(r * width + c)] =
          areaMean(image, region.x0 + (c + 0.5) * sx, region.y0 + (r + 0.5) * sy, sx, sy);
  return out;
}

std::vector<float> rectifyToMidPlane(const media::Image& image, const Camera& source, const Camera& front, const GridSize& grid) {
  const double plane = 0.5 * static_cast<double>(grid.z);
  auto onPlane = [&](double u, double v) {  // the point of the mid-plane that front's pixel coordinates (u, v) see
    const Ray ray = front.ray(u, v);
    if (std::abs(ray.direction.z) < 1e-12) throw Error("rectifyToMidPlane: the front camera does not face the mid-plane");
    const double t = (plane - ray.origin.z) / ray.direction.z;
    const auto p = source.project(ray.origin + t * ray.direction);
    if (!p) throw Error("calibration: the box's mid-plane lies behind the input camera");
    return *p;
  };
  std::vector<float> out(static_cast<std::size_t>(front.width * front.height), 0.0f);
  for (int r = 0; r < front.height; ++r)
    for (int c = 0; c < front.width; ++c) {
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      for (const auto& [u, v] : {std::pair{c, r}, std::pair{c + 1, r}, std::pair{c, r + 1}, std::pair{c + 1, r + 1}}) {
        const auto p = onPlane(u, v);
        x0 = std::min(x0, p[0]);
        x1 = std::max(x1, p[0]);
        y0 = std::min(y0, p[1]);
        y1 = std::max(y1, p[1]);
      }
      out[static_cast<std::size_t>(r * front.width + c)] = areaMean(image, 0.5 * (x0 + x1), 0.5 * (y0 + y1), x1 - x0, y1 - y0);
    }
  return out;
}

FrontViews readFrontViews(const InputOptions& o, const Preset& preset) {
  if (o.first < 0) throw Error("--frames: the first frame must be >= 0");
  if (!(o.threshold >= 0 && o.threshold < 1)) throw Error("--threshold: expected a number in [0, 1)");
  if (!(o.target > 0 && o.target <= 1)) throw Error("--target: expected a number in (0, 1]");
  Frames input = readInput(o);
  FrontViews views;
  views.sourceWidth = input.images[0].width;
  views.sourceHeight = input.images[0].height;
  views.frameRate = input.frameRate;
  views.mapping = chooseMapping(input.images, o);
  applyMapping(input.images, views.mapping);
  const double aspect = static_cast<double>(preset.imageWidth) / preset.imageHeight;
  switch (o.framing) {
    case Framing::Box:
      views.region = {0, 0, static_cast<double>(views.sourceWidth), static_cast<double>(views.sourceHeight)};
      break;
    case Framing::Auto:
      views.region = autoRegion(input.images, aspect, o.input.string());
      break;
    case Framing::Calibrated: {
      if (o.calibration.empty()) throw Error("--framing calibrated needs --camera info.json[:VIDEO]");
      const Calibration calibration = readCalibration(o.calibration);
      const std::string name = o.camera.empty() ? o.input.filename().string() : o.camera;
      const CalibratedView& view = calibration.view(name);
      if (std::abs(static_cast<double>(view.width) / view.height - static_cast<double>(views.sourceWidth) / views.sourceHeight) > 0.01)
        throw Error(o.calibration.string() + ": camera '" + name + "' is " + std::to_string(view.width) + "x" +
                    std::to_string(view.height) + ", the input frames " + std::to_string(views.sourceWidth) + "x" +
                    std::to_string(views.sourceHeight) + " (another aspect ratio)");
      views.camera = calibratedCamera(view, calibration.box, preset.grid, views.sourceWidth);
      views.region = calibratedRegion(*views.camera, preset.grid, aspect);
      break;
    }
  }
  for (const media::Image& frame : input.images)
    views.inputFrames.push_back(resampleRegion(frame, views.region, preset.imageWidth, preset.imageHeight));
  const Camera front = orbitCamera(0, preset.grid, preset.imageWidth, preset.imageHeight);
  views.rectified = views.camera && !o.orthographic;
  if (views.rectified) {
    views.inputCamera = windowCamera(*views.camera, views.region.x0, views.region.y0, views.region.width,
                                     views.region.height, preset.imageWidth, preset.imageHeight);
    for (const media::Image& frame : input.images)
      views.frames.push_back(rectifyToMidPlane(frame, *views.camera, front, preset.grid));
  } else {
    views.inputCamera = front;
    views.frames = views.inputFrames;
  }
  return views;
}

nlohmann::json FrontViews::describe() const {
  return {{"source_size", {sourceWidth, sourceHeight}},
          {"frame_rate", frameRate},
          {"region", {{"x0", region.x0}, {"y0", region.y0}, {"width", region.width}, {"height", region.height}}},
          {"intensity",
           {{"black", mapping.black}, {"gain", mapping.gain}, {"threshold", mapping.threshold},
            {"background", mapping.perPixelBackground ? "first frame, per pixel" : "level"},
            {"formula", "w = clamp(max(0, (v - black) * gain - threshold) / (1 - threshold), 0, 1)"}}},
          {"front_views", rectified ? "the footage rectified onto the box's mid-plane; fitted through the input camera"
                                    : "the region as the orthographic front view"}};
}

}  // namespace smokesvd::reconstruct
