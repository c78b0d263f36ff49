// The calibration check of real footage: each calibrated camera's video frame next to where that camera
// sees the volume box. A correct calibration puts the projected box around the smoke in every view.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/camera/calibration.h"
#include "pipeline/media/image.h"

namespace smokesvd::render {

struct ViewCheck {
  std::string fileName;
  Camera camera;                  // at the tile size
  media::Image frame;             // the video frame, gray, resized to the tile size
  std::array<double, 2> centre{}; // projected box centre, pixel coordinates of the tile
  bool centreInFrame = false;
  float brightnessAtCentre = 0;   // mean frame value in a 5x5 window at the centre (0 when outside)
  float frameMean = 0;            // mean value of the whole frame
};

// Decodes frame `frame` of every view's video (file_name resolved in `videoFolder`; needs ffmpeg) and
// projects the box of `grid` through each camera built `tileWidth` pixels wide. Views sorted by file name.
std::vector<ViewCheck> checkCalibration(const Calibration& calibration, const std::filesystem::path& videoFolder,
                                        int frame, int tileWidth, const GridSize& grid);

// Images of one height side by side (all gray or all RGB).
media::Image besideEachOther(const std::vector<media::Image>& images);

}  // namespace smokesvd::render
