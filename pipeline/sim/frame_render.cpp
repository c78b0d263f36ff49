#include "pipeline/sim/frame_render.h"

#include <cstdio>

#include "pipeline/camera/camera.h"
#include "pipeline/media/image.h"
#include "pipeline/sim/outputs.h"

namespace smokesvd::sim {

render::RenderSettings renderSettings(const RenderSpec& spec) {
  render::RenderSettings settings;
  settings.step = static_cast<float>(spec.step);
  settings.absorption = static_cast<float>(spec.absorption);
  settings.ambient = static_cast<float>(spec.ambient);
  if (spec.lightDirection) {
    render::DirectionalLight light;
    light.direction = *spec.lightDirection;
    light.intensity = static_cast<float>(spec.lightIntensity);
    light.absorption = static_cast<float>(spec.lightAbsorption);
    settings.light = light;
  }
  return settings;
}

FrameRenderer::FrameRenderer(Context& context, const Scene& scene) : spec_(scene.render) {
  const GridSize grid{scene.resolution[2], scene.resolution[1], scene.resolution[0]};
  const std::vector<Camera> cameras = orbitCameras(orbitAngles(spec_.views), grid, spec_.width, spec_.height);
  views_ = render::uploadViews(context, cameras);
  images_ = Tensor(context, {spec_.views, 1, spec_.height, spec_.width});
}

void FrameRenderer::render(const Simulator& simulator) {
  Stream stream(simulator.density().context());
  render::render(stream, simulator.density(), views_, renderSettings(spec_), images_);
  stream.submit();
}

void FrameRenderer::write(const std::filesystem::path& directory, const Simulator& simulator) {
  render(simulator);
  const std::vector<float> pixels = images_.download();
  const std::size_t perView = static_cast<std::size_t>(spec_.width) * static_cast<std::size_t>(spec_.height);
  const std::string frame = frameName(simulator.frame() - 1);
  for (int v = 0; v < spec_.views; ++v) {
    char view[16];
    std::snprintf(view, sizeof view, "view_%02d", v);
    const std::filesystem::path folder = directory / "renders" / view;
    std::filesystem::create_directories(folder);
    media::Image image = media::Image::gray(spec_.width, spec_.height);
    for (std::size_t i = 0; i < perView; ++i)
      image.values[i] = pixels[static_cast<std::size_t>(v) * perView + i] * static_cast<float>(spec_.exposure);
    media::writePng(folder / (frame + ".png"), image, 16);
  }
}

}  // namespace smokesvd::sim
