#include "pipeline/reconstruct/run_outputs.h"

#include <cmath>

#include "nets/io/npy.h"
#include "pipeline/media/image.h"
#include "pipeline/media/video.h"
#include "pipeline/networks/view_slots.h"
#include "pipeline/render/render_images.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

namespace smokesvd::reconstruct {
namespace fs = std::filesystem;
namespace {

const std::vector<std::string>& runFolders() {
  static const std::vector<std::string> folders{"fields", "renders", "side", "input"};
  return folders;
}
const std::vector<std::string>& runFiles() {
  static const std::vector<std::string> files{"run.json", "checkpoint.npz", "scene.json", "flags.npz",
                                              "input.mp4", "side.mp4", "orbit.mp4", "contact.png"};
  return files;
}

media::Image imageOf(const std::vector<float>& values, int width, int height) {
  media::Image image = media::Image::gray(width, height);
  image.values = values;
  return image;
}

std::string viewFolder(int slot) {
  char name[16];
  std::snprintf(name, sizeof name, "view_%02d", slot);
  return name;
}

}  // namespace

RunFolder::RunFolder(fs::path root) : root_(std::move(root)) {}

void RunFolder::requireEmptyOrAbsent() const {
  if (!fs::exists(root_)) return;
  if (!fs::is_directory(root_)) throw Error(root_.string() + ": exists and is not a folder");
  if (!fs::is_empty(root_))
    throw Error(root_.string() + ": is not empty and holds no reconstruction; choose another --out (nothing there is touched)");
}

void RunFolder::clear() const {
  for (const std::string& f : runFolders()) fs::remove_all(root_ / f);
  for (const std::string& f : runFiles()) fs::remove(root_ / f);
}

void RunFolder::prepare() const {
  try {
    for (const char* f : {"fields", "side", "input"}) fs::create_directories(root_ / f);
    for (int slot = 0; slot < networks::kSlots; ++slot) fs::create_directories(root_ / "renders" / viewFolder(slot));
  } catch (const fs::filesystem_error& e) {
    throw Error(root_.string() + ": cannot create the output folders (" + e.code().message() + ")");
  }
}

void RunFolder::removeTemporaries() const {
  if (!fs::exists(root_)) return;
  for (const auto& entry : fs::recursive_directory_iterator(root_))
    if (entry.is_regular_file() && entry.path().extension() == ".tmp") fs::remove(entry.path());
}

void RunFolder::writeFlags(const std::vector<float>& flags, const GridSize& grid) const {
  std::vector<int32_t> ints(flags.begin(), flags.end());
  io::writeNpz(root_ / "flags.npz", {{"flags", io::NpyArray::fromInts(grid.volume(), ints)}});
}

void RunFolder::writeFrame(int frame, const Tensor& density, const Tensor& inflow, const Tensor& views, const Tensor& side,
                           const Tensor& front) const {
  const std::string name = sim::frameName(frame);
  io::writeNpz(root_ / "fields" / ("density_" + name + ".npz"), {{"density", io::NpyArray::fromFloats(density.shape(), density.download())}});
  io::writeNpz(root_ / "fields" / ("inflow_" + name + ".npz"), {{"inflow", io::NpyArray::fromFloats(inflow.shape(), inflow.download())}});
  const int h = static_cast<int>(views.size(2)), w = static_cast<int>(views.size(3));
  const std::vector<float> all = views.download();
  const std::size_t pixels = static_cast<std::size_t>(h * w);
  for (int slot = 0; slot < networks::kSlots; ++slot)
    media::writePng(root_ / "renders" / viewFolder(slot) / (name + ".png"),
                    imageOf(std::vector<float>(all.begin() + static_cast<std::ptrdiff_t>(slot * pixels),
                                               all.begin() + static_cast<std::ptrdiff_t>((slot + 1) * pixels)), w, h),
                    16);
  media::writePng(root_ / "side" / (name + ".png"), imageOf(side.download(), w, h), 16);
  media::writePng(root_ / "input" / (name + ".png"), imageOf(front.download(), w, h), 16);
}

void RunFolder::writeVelocity(int frame, const Tensor& velocity) const {
  const fs::path path = root_ / "fields" / ("velocity_" + sim::frameName(frame) + ".npz");
  const io::NpyArray density = io::readNpzMember(root_ / "fields" / ("density_" + sim::frameName(frame) + ".npz"), "density");
  const Shape& s = density.shape;  // [D, H, W]
  const auto cells = static_cast<std::size_t>(numElements(s));
  std::vector<float> interleaved(3 * cells, 0.0f);
  if (velocity.defined()) {
    const std::vector<float> planar = velocity.download();
    for (std::size_t c = 0; c < cells; ++c)
      for (std::size_t a = 0; a < 3; ++a) interleaved[3 * c + a] = planar[a * cells + c];
  }
  io::writeNpz(path, {{"velocity", io::NpyArray::fromFloats({s[0], s[1], s[2], 3}, interleaved)}});
}

nlohmann::json RunFolder::writeSummaries(Context& context, int frames, double frameRate, const render::RenderSettings& look,
                                         const Preset& preset) const {
  nlohmann::json written = nlohmann::json::object();
  std::vector<media::Image> input, side, orbit;
  std::vector<std::vector<media::Image>> novel;  // contact-sheet renders of a few frames
  const std::vector<double> novelAngles{45.0, 67.5, 112.5, 135.0};
  const int rows = std::min(frames, 4);
  std::vector<int> sheetFrames;
  for (int r = 0; r < rows; ++r) sheetFrames.push_back(rows == 1 ? 0 : r * (frames - 1) / (rows - 1));
  for (int t = 0; t < frames; ++t) {
    const std::string name = sim::frameName(t) + ".png";
    input.push_back(media::readPng(root_ / "input" / name));
    side.push_back(media::readPng(root_ / "side" / name));
    const io::NpyArray d = io::readNpzMember(root_ / "fields" / ("density_" + sim::frameName(t) + ".npz"), "density");
    const Tensor density = Tensor::fromHost(context, d.shape, d.toFloat());
    const std::vector<Camera> turning{networks::orbitCameraAt(preset, 360.0 * t / std::max(frames, 1))};
    orbit.push_back(render::renderImages(context, density, turning, look)[0]);
    if (std::find(sheetFrames.begin(), sheetFrames.end(), t) != sheetFrames.end()) {
      std::vector<Camera> cameras;
      for (const double a : novelAngles) cameras.push_back(networks::orbitCameraAt(preset, a));
      novel.push_back(render::renderImages(context, density, cameras, look));
    }
  }
  // contact.png: rows of frames; columns input | side | 45 | 67.5 | 112.5 | 135 degrees; 2-pixel gaps.
  const int w = preset.imageWidth, h = preset.imageHeight, gap = 2, columns = 2 + static_cast<int>(novelAngles.size());
  media::Image sheet = media::Image::gray(columns * (w + gap) + gap, rows * (h + gap) + gap, 0.25f);
  for (int r = 0; r < rows; ++r) {
    const int t = sheetFrames[static_cast<std::size_t>(r)];
    std::vector<const media::Image*> tiles{&input[static_cast<std::size_t>(t)], &side[static_cast<std::size_t>(t)]};
    for (const media::Image& n : novel[static_cast<std::size_t>(r)]) tiles.push_back(&n);
    for (int c = 0; c < columns; ++c)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          sheet.at(gap + r * (h + gap) + y, gap + c * (w + gap) + x) = std::clamp(tiles[static_cast<std::size_t>(c)]->at(y, x), 0.0f, 1.0f);
  }
  media::writePng(root_ / "contact.png", media::resize(sheet, sheet.width * 3, sheet.height * 3));
  written["contact.png"] = "rows: frames " + nlohmann::json(sheetFrames).dump() + "; columns: input, side, 45, 67.5, 112.5, 135 degrees";
  if (!media::findFfmpeg()) {
    written["videos"] = "skipped: ffmpeg not found";
    return written;
  }
  media::writeVideo(root_ / "input.mp4", input, frameRate);
  media::writeVideo(root_ / "side.mp4", side, frameRate);
  media::writeVideo(root_ / "orbit.mp4", orbit, frameRate);
  written["videos"] = {"input.mp4", "side.mp4", "orbit.mp4 (one turn about the vertical axis over the clip)"};
  return written;
}

}  // namespace smokesvd::reconstruct
