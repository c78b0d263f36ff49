// Density to images, as every command writes them: `smokesvd render`, the simulator's frame renders and
// the reconstruction call this one function.
//
//   image(view, row, column) = gain * radiance(view, row, column)   (the renderer of render/renderer.h)
//
// Cameras that share an image size render in one dispatch; images come back in the cameras' order, gray,
// row 0 at the top. PNG writing clamps them to [0, 1] (media/image.h).
#pragma once

#include <span>
#include <vector>

#include "pipeline/camera/camera.h"
#include "pipeline/media/image.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::render {

// Renders `density` [D, H, W] (a device tensor) through every camera and downloads the images.
std::vector<media::Image> renderImages(Context& context, const Tensor& density, std::span<const Camera> cameras,
                                       const RenderSettings& settings, float gain = 1.0f);

// The calibration check's tile: the gray video frame as RGB with `render` (same size) added to the blue
// channel at half strength (clamped to 1), and the box of `grid` as `camera` sees it drawn on top.
media::Image overlayTile(const media::Image& frame, const media::Image& render, const Camera& camera,
                         const GridSize& grid);

}  // namespace smokesvd::render
