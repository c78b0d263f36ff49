// Renders of every simulated frame: the density seen from the scene's orbit views (evenly on [0°, 180°),
// orthographic, the renderer of pipeline/render), written as renders/view_VV/NNNN.png, 8-bit gray,
// value = clamp(exposure · radiance, 0, 1).
#pragma once

#include <filesystem>

#include "pipeline/render/renderer.h"
#include "pipeline/sim/simulator.h"

namespace smokesvd::sim {

render::RenderSettings renderSettings(const RenderSpec& spec);

class FrameRenderer {
 public:
  FrameRenderer(Context& context, const Scene& scene);
  // Renders the simulator's density into images() [views, 1, height, width].
  void render(const Simulator& simulator);
  // render() and the PNGs of the simulator's last completed frame.
  void write(const std::filesystem::path& directory, const Simulator& simulator);
  const Tensor& images() const { return images_; }

 private:
  RenderSpec spec_;
  render::ViewSet views_;
  Tensor images_;
};

}  // namespace smokesvd::sim
