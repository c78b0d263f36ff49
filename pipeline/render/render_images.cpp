#include "pipeline/render/render_images.h"

#include <algorithm>
#include <map>
#include <utility>

#include "pipeline/render/box_overlay.h"
#include "runtime/error.h"

namespace smokesvd::render {

std::vector<media::Image> renderImages(Context& context, const Tensor& density, std::span<const Camera> cameras,
                                       const RenderSettings& settings, float gain) {
  std::map<std::pair<int, int>, std::vector<std::size_t>> bySize;  // (width, height) -> camera indices
  for (std::size_t i = 0; i < cameras.size(); ++i) bySize[{cameras[i].width, cameras[i].height}].push_back(i);
  std::vector<media::Image> images(cameras.size());
  for (const auto& [size, indices] : bySize) {
    std::vector<Camera> group;
    for (std::size_t i : indices) group.push_back(cameras[i]);
    const ViewSet views = uploadViews(context, group);
    Tensor rendered(context, {views.views, 1, views.height, views.width});
    Stream stream(context);
    render(stream, density, views, settings, rendered);
    stream.submit();
    const std::vector<float> values = rendered.download();
    const auto pixels = static_cast<std::size_t>(views.width) * static_cast<std::size_t>(views.height);
    for (std::size_t v = 0; v < indices.size(); ++v) {
      media::Image image = media::Image::gray(views.width, views.height);
      for (std::size_t p = 0; p < pixels; ++p) image.values[p] = gain * values[v * pixels + p];
      images[indices[v]] = std::move(image);
    }
  }
  return images;
}

media::Image overlayTile(const media::Image& frame, const media::Image& render, const Camera& camera,
                         const GridSize& grid) {
  if (render.width != frame.width || render.height != frame.height || render.channels != 1)
    throw Error("overlay tile: the render (" + std::to_string(render.width) + "x" + std::to_string(render.height) +
                ") must be gray and of the frame's size " + std::to_string(frame.width) + "x" +
                std::to_string(frame.height));
  media::Image rgb = media::toRgb(frame);
  for (int r = 0; r < rgb.height; ++r)
    for (int c = 0; c < rgb.width; ++c) rgb.at(r, c, 2) = std::min(1.0f, rgb.at(r, c, 2) + 0.5f * render.at(r, c));
  drawProjectedBox(rgb, camera, grid);
  return rgb;
}

}  // namespace smokesvd::render
