#include "pipeline/render/box_overlay.h"

#include <algorithm>
#include <cmath>

#include "pipeline/camera/calibration.h"
#include "runtime/error.h"

namespace smokesvd::render {
namespace {

using Point = std::array<double, 2>;

void drawDisc(media::Image& rgb, const Point& p, double radius, const std::array<float, 3>& colour) {
  const int r0 = std::max(0, static_cast<int>(std::floor(p[1] - radius)));
  const int r1 = std::min(rgb.height - 1, static_cast<int>(std::ceil(p[1] + radius)));
  const int c0 = std::max(0, static_cast<int>(std::floor(p[0] - radius)));
  const int c1 = std::min(rgb.width - 1, static_cast<int>(std::ceil(p[0] + radius)));
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c) {
      const double du = c + 0.5 - p[0], dv = r + 0.5 - p[1];
      if (du * du + dv * dv <= radius * radius)
        for (int ch = 0; ch < 3; ++ch) rgb.at(r, c, ch) = colour[static_cast<std::size_t>(ch)];
    }
}

void drawLine(media::Image& rgb, const Point& a, const Point& b, double thickness, const std::array<float, 3>& colour) {
  const double length = std::hypot(b[0] - a[0], b[1] - a[1]);
  const int steps = std::max(1, static_cast<int>(std::ceil(length * 2)));
  for (int i = 0; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    drawDisc(rgb, {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])}, 0.5 * thickness, colour);
  }
}

}  // namespace

void drawProjectedBox(media::Image& rgb, const Camera& camera, const GridSize& grid, const OverlayStyle& style) {
  if (rgb.channels != 3 || rgb.width != camera.width || rgb.height != camera.height)
    throw Error("box overlay: needs an RGB image of the camera's size " + std::to_string(camera.width) + "x" +
                std::to_string(camera.height));
  const std::array<Vec3, 8> corners = gridCorners(grid);
  for (std::size_t i = 0; i < 8; ++i)
    for (std::size_t bit : {1u, 2u, 4u}) {
      const std::size_t j = i | bit;
      if (j == i) continue;
      const auto a = camera.project(corners[i]), b = camera.project(corners[j]);
      if (a && b) drawLine(rgb, *a, *b, style.thickness, style.edgeColour);
    }
  if (const auto centre = camera.project(grid.centre())) {
    const double arm = 4 * style.thickness;
    drawLine(rgb, {(*centre)[0] - arm, (*centre)[1]}, {(*centre)[0] + arm, (*centre)[1]}, style.thickness,
             style.centreColour);
    drawLine(rgb, {(*centre)[0], (*centre)[1] - arm}, {(*centre)[0], (*centre)[1] + arm}, style.thickness,
             style.centreColour);
  }
}

}  // namespace smokesvd::render
