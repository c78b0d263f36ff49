// Plain CPU references of the simulation kernels, in double, for the GPU tests. Volumes are flat
// [nz, ny, nx] arrays (x fastest), vector fields planar [3, nz, ny, nx]; flags hold 1 fluid, 2 obstacle,
// 4 empty, and cells outside the grid count as obstacle.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pipeline/physics/grid.h"
#include "pipeline/physics/sources.h"

namespace smokesvd::testing::ref {

using Field = std::vector<double>;

struct Cell {
  int64_t i, j, k;
};

class FlagView {
 public:
  FlagView(const GridSize& grid, const std::vector<float>& flags) : grid_(grid), flags_(flags) {}
  bool inside(Cell c) const { return c.i >= 0 && c.j >= 0 && c.k >= 0 && c.i < grid_.x && c.j < grid_.y && c.k < grid_.z; }
  int64_t index(Cell c) const { return c.i + grid_.x * (c.j + grid_.y * c.k); }
  uint32_t flag(Cell c) const { return inside(c) ? static_cast<uint32_t>(flags_[index(c)]) : 2u; }
  bool fluid(Cell c) const { return (flag(c) & 1u) != 0; }
  bool obstacle(Cell c) const { return (flag(c) & 2u) != 0; }
  Cell cell(int64_t index) const { return {index % grid_.x, (index / grid_.x) % grid_.y, index / (grid_.x * grid_.y)}; }
  const GridSize& grid() const { return grid_; }

 private:
  GridSize grid_;
  const std::vector<float>& flags_;
};

Cell step(Cell c, int axis, int64_t amount);

// Random flags: an obstacle outer layer, inside fluid with some obstacle and empty cells.
std::vector<float> randomFlags(const GridSize& grid, uint64_t seed, double obstacleShare = 0.15,
                               double emptyShare = 0.1);

Field widen(const std::vector<float>& values);

// Pressure solver pieces (mirror shaders/physics/pressure_*.comp and multigrid_*.comp).
Field divergence(const FlagView& flags, const Field& velocity);  // 0 outside the fluid
Field laplacian(const FlagView& flags, const Field& x);          // A x, 0 outside the fluid
std::vector<int> nonObstacleNeighbours(const FlagView& flags);
Field jacobiSweep(const FlagView& flags, const Field& rhs, const Field& x, double weight);
Field restrictResidual(const FlagView& fine, const Field& rhs, const Field& x, const FlagView& coarse, double scale);
std::vector<float> stencilMasks(const FlagView& flags);  // bit layout in shaders/physics/obstacle_flags.glsl
std::vector<float> coarsenFlags(const FlagView& fine, const GridSize& coarse);
Field prolongAdd(const FlagView& fine, const Field& x, const Field& coarse, const GridSize& coarseGrid);
Field correctVelocity(const FlagView& flags, const Field& pressure, const Field& velocity);

// Forces (mirror shaders/physics/buoyancy.comp, force_field.comp, vorticity_*.comp).
using Vec3d = std::array<double, 3>;
bool forceActs(const FlagView& flags, Cell c, int axis);
Field addBuoyancy(const FlagView& flags, const Field& density, const Field& temperature, const Field& velocity,
                  const Vec3d& uniform, const Vec3d& perDensity, const Vec3d& perTemperature, double dt);
Field addForceField(const FlagView& flags, const Field& force, const Field& velocity, double dt);
Field vorticityField(const GridSize& grid, const Field& velocity);  // [4, D, H, W]
Field vorticityForce(const GridSize& grid, const Field& vorticity, double strength);  // [3, D, H, W]
Field addVorticityConfinement(const FlagView& flags, const Field& vorticity, const Field& velocity, double strength,
                              double dt);

// Inflow (mirror shaders/physics/inflow_*.comp).
double sourceCoverage(const physics::SourceState& source, const Vec3d& p);
double sourceNoise(const physics::SourceState& source, const Vec3d& p);
void inflowFields(const FlagView& flags, const Field& density, const Field& temperature,
                  const std::vector<physics::SourceState>& sources, double dt, Field& densityInflow,
                  Field& temperatureInflow);
Field applySourceVelocity(const FlagView& flags, const std::vector<physics::SourceState>& sources,
                          const Field& velocity);

double maxAbs(const Field& values);
double dot(const Field& a, const Field& b);

}  // namespace smokesvd::testing::ref
