#include "pipeline/render/calibration_check.h"

#include <algorithm>

#include "pipeline/media/video.h"
#include "runtime/error.h"

namespace smokesvd::render {

std::vector<ViewCheck> checkCalibration(const Calibration& calibration, const std::filesystem::path& videoFolder,
                                        int frame, int tileWidth, const GridSize& grid) {
  std::vector<CalibratedView> views = calibration.views;
  std::sort(views.begin(), views.end(), [](const auto& a, const auto& b) { return a.fileName < b.fileName; });
  std::vector<ViewCheck> checks;
  for (const CalibratedView& view : views) {
    ViewCheck check;
    check.fileName = view.fileName;
    check.camera = calibratedCamera(view, calibration.box, grid, tileWidth);
    const media::Image full = media::readVideoFrames(videoFolder / view.fileName, frame, 1).front();
    if (full.width * view.height != full.height * view.width)
      throw Error((videoFolder / view.fileName).string() + ": frames are " + std::to_string(full.width) + "x" +
                  std::to_string(full.height) + " but camera_hw says " + std::to_string(view.width) + "x" +
                  std::to_string(view.height));
    check.frame = media::resize(full, check.camera.width, check.camera.height);
    double sum = 0;
    for (float v : check.frame.values) sum += v;
    check.frameMean = static_cast<float>(sum / static_cast<double>(check.frame.values.size()));
    if (const auto centre = check.camera.project(grid.centre())) {
      check.centre = *centre;
      const int column = static_cast<int>(std::floor((*centre)[0])), row = static_cast<int>(std::floor((*centre)[1]));
      check.centreInFrame = column >= 0 && row >= 0 && column < check.frame.width && row < check.frame.height;
      if (check.centreInFrame) {
        double window = 0;
        int count = 0;
        for (int r = std::max(0, row - 2); r <= std::min(check.frame.height - 1, row + 2); ++r)
          for (int c = std::max(0, column - 2); c <= std::min(check.frame.width - 1, column + 2); ++c, ++count)
            window += check.frame.at(r, c);
        check.brightnessAtCentre = static_cast<float>(window / count);
      }
    }
    checks.push_back(std::move(check));
  }
  return checks;
}

media::Image besideEachOther(const std::vector<media::Image>& images) {
  if (images.empty()) throw Error("besideEachOther: no images");
  media::Image out;
  out.height = images[0].height;
  out.channels = images[0].channels;
  for (const media::Image& image : images) {
    if (image.height != out.height || image.channels != out.channels)
      throw Error("besideEachOther: images differ in height or channels");
    out.width += image.width;
  }
  out.values.resize(static_cast<std::size_t>(out.width * out.height * out.channels));
  int offset = 0;
  for (const media::Image& image : images) {
    for (int r = 0; r < image.height; ++r)
      for (int c = 0; c < image.width; ++c)
        for (int ch = 0; ch < image.channels; ++ch) out.at(r, offset + c, ch) = image.at(r, c, ch);
    offset += image.width;
  }
  return out;
}

}  // namespace smokesvd::render
