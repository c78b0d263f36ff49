#include "pipeline/sim/frame_render.h"

#include <cstdio>

#include "pipeline/media/image.h"
#include "pipeline/render/render_images.h"
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

FrameRenderer::FrameRenderer(const Scene& scene)
    : spec_(scene.render),
      cameras_(orbitCameras(orbitAngles(spec_.views), scene.resolution, spec_.width, spec_.height)) {}

void FrameRenderer::write(RunFiles& files, const Simulator& simulator) const {
  const std::vector<media::Image> images =
      render::renderImages(simulator.density().context(), simulator.density(), cameras_, renderSettings(spec_),
                           static_cast<float>(spec_.exposure));
  const std::string frame = frameName(simulator.frame() - 1);
  for (std::size_t v = 0; v < images.size(); ++v) {
    char view[32];
    std::snprintf(view, sizeof view, "view_%02zu", v);
    std::filesystem::create_directories(files.directory() / "renders" / view);
    media::writePng(files.add("renders/" + std::string(view) + "/" + frame + ".png"), images[v], 16);
  }
}

}  // namespace smokesvd::sim
