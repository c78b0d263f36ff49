// Drawing a camera's view of the volume box onto an RGB image: the twelve projected edges of the grid box
// and a cross at its centre (the calibration check of `smokesvd render --overlay-frame`).
#pragma once

#include <array>

#include "pipeline/camera/camera.h"
#include "pipeline/media/image.h"

namespace smokesvd::render {

struct OverlayStyle {
  std::array<float, 3> edgeColour{1.0f, 0.55f, 0.0f};
  std::array<float, 3> centreColour{0.0f, 0.9f, 1.0f};
  double thickness = 1.5;  // pixels
};

// Draws the projected box of `grid` as seen by `camera` (whose image size must be the image's) onto `rgb`.
void drawProjectedBox(media::Image& rgb, const Camera& camera, const GridSize& grid, const OverlayStyle& style = {});

}  // namespace smokesvd::render
