// Plain CPU references in double for the render kernels: the same sampling rules, one loop per formula.
#pragma once

#include <vector>

#include "pipeline/camera/camera.h"
#include "pipeline/render/renderer.h"

namespace smokesvd::testing::reference {

double sampleZero(const std::vector<double>& volume, const GridSize& grid, const Vec3& p);
double sampleClamped(const std::vector<double>& volume, const GridSize& grid, const Vec3& p);

std::vector<double> lightTransmittance(const std::vector<double>& density, const GridSize& grid,
                                       const render::DirectionalLight& light);
// Images [V, 1, h, w] of `density` through `cameras`.
std::vector<double> render(const std::vector<double>& density, const GridSize& grid,
                           const std::vector<Camera>& cameras, const render::RenderSettings& settings);
// images [V, 1, h, w] -> [V, D, H, W]
std::vector<double> lift(const std::vector<double>& images, const std::vector<Camera>& cameras, const GridSize& grid);
// volume [C, D, H, W] -> rotated
std::vector<double> rotate(const std::vector<double>& volume, int64_t channels, const GridSize& grid,
                           double angleDegrees);

}  // namespace smokesvd::testing::reference
