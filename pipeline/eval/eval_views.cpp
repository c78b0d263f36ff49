#include "pipeline/eval/eval_views.h"

#include <algorithm>
#include <map>

#include "pipeline/render/render_images.h"
#include "runtime/error.h"
#include "runtime/tensor.h"

namespace smokesvd::eval {

const char* groupName(ViewGroup group) {
  switch (group) {
    case ViewGroup::Input: return "input";
    case ViewGroup::Side: return "side";
    case ViewGroup::Novel: return "novel";
  }
  return "";
}

Units parseUnits(const std::string& text) {
  if (text == "mapped") return Units::Mapped;
  if (text == "footage") return Units::Footage;
  throw Error("--units: expected mapped or footage, got '" + text + "'");
}

void clampUnit(media::Image& image) {
  for (float& v : image.values) v = std::clamp(v, 0.0f, 1.0f);
}

void mapIntensity(media::Image& image, const reconstruct::IntensityMapping& mapping, const media::Image* background) {
  if (background)
    for (std::size_t i = 0; i < image.values.size(); ++i) image.values[i] -= background->values[i];
  std::vector<media::Image> one{std::move(image)};
  reconstruct::applyMapping(one, mapping);
  image = std::move(one[0]);
}

void mapBack(media::Image& render, const reconstruct::IntensityMapping& mapping, const media::Image* background) {
  for (std::size_t i = 0; i < render.values.size(); ++i)
    render.values[i] = mapping.black + render.values[i] / mapping.gain + (background ? background->values[i] : 0.0f);
  clampUnit(render);
}

media::Image mirrored(const media::Image& image) {
  media::Image m = image;
  for (int r = 0; r < image.height; ++r)
    for (int c = 0; c < image.width; ++c) m.at(r, c) = image.at(r, image.width - 1 - c);
  return m;
}

std::vector<media::Image> renderViews(Context& context, const std::vector<float>& density, const GridSize& grid,
                                      const std::vector<EvalView>& views, const render::RenderSettings& look) {
  const Tensor volume = Tensor::fromHost(context, grid.volume(), density);
  std::vector<Camera> cameras;
  for (const EvalView& view : views) {
    const int s = view.supersample;
    if (s < 1) throw Error("eval: view " + view.name + " has supersampling " + std::to_string(s) + " (expected >= 1)");
    cameras.push_back(s == 1 ? view.camera
                             : windowCamera(view.camera, 0, 0, view.camera.width, view.camera.height, s * view.camera.width,
                                            s * view.camera.height));
  }
  std::vector<media::Image> fine = render::renderImages(context, volume, cameras, look);
  std::vector<media::Image> images;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const int s = views[v].supersample, width = views[v].camera.width, height = views[v].camera.height;
    media::Image image = media::Image::gray(width, height);
    for (int r = 0; r < height; ++r)
      for (int c = 0; c < width; ++c) {
        double sum = 0;
        for (int i = 0; i < s; ++i)
          for (int j = 0; j < s; ++j) sum += fine[v].at(r * s + i, c * s + j);
        image.at(r, c) = static_cast<float>(sum / (s * s));
      }
    clampUnit(image);
    images.push_back(std::move(image));
  }
  return images;
}

}  // namespace smokesvd::eval
