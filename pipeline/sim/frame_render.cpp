#include "pipeline/sim/frame_render.h"

#include <algorithm>
#include <cstdio>

#include "pipeline/camera/camera.h"
#include "pipeline/sim/outputs.h"
#include "runtime/error.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STB_IMAGE_WRITE_STATIC
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace smokesvd::sim {
namespace {

// 8-bit gray PNG of values in [0, 1], row 0 at the top, written under a temporary name and renamed.
void writeGrayPng(const std::filesystem::path& path, const std::vector<float>& values, int width, int height) {
  std::vector<unsigned char> bytes(values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    bytes[i] = static_cast<unsigned char>(std::clamp(values[i], 0.0f, 1.0f) * 255.0f + 0.5f);
  const std::filesystem::path temporary = path.string() + ".tmp";
  if (!stbi_write_png(temporary.c_str(), width, height, 1, bytes.data(), width))
    throw Error(temporary.string() + ": cannot write the PNG image");
  std::filesystem::rename(temporary, path);
}

}  // namespace

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
    std::vector<float> image(pixels.begin() + static_cast<std::ptrdiff_t>(v * perView),
                             pixels.begin() + static_cast<std::ptrdiff_t>((v + 1) * perView));
    for (float& value : image) value *= static_cast<float>(spec_.exposure);
    writeGrayPng(folder / (frame + ".png"), image, spec_.width, spec_.height);
  }
}

}  // namespace smokesvd::sim
