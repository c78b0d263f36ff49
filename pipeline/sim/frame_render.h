// Renders of every simulated frame: the density seen from the scene's orbit views (evenly on [0°, 180°),
// orthographic, through render::renderImages), written as renders/view_VV/NNNN.png, 16-bit gray,
// value = clamp(exposure · radiance, 0, 1).
#pragma once

#include <filesystem>
#include <vector>

#include "pipeline/camera/camera.h"
#include "pipeline/render/renderer.h"
#include "pipeline/sim/run_files.h"
#include "pipeline/sim/simulator.h"

namespace smokesvd::sim {

render::RenderSettings renderSettings(const RenderSpec& spec);

class FrameRenderer {
 public:
  explicit FrameRenderer(const Scene& scene);
  // The PNGs of the simulator's last completed frame.
  void write(RunFiles& files, const Simulator& simulator) const;

 private:
  RenderSpec spec_;
  std::vector<Camera> cameras_;
};

}  // namespace smokesvd::sim
