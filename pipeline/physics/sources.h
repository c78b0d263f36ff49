// Inflow sources: spheres, boxes and cylinders that feed density and temperature into the smoke and may
// set the velocity they cover. A step evaluates each source's state at the current time (the scene's
// keyframes do that) and writes the states into a source table on the device; the kernels read it.
//
// Density inflow is a field for advection to add (ρ_next = A(ρ, u) + inflow), so that saved frames obey
// that relation exactly: a `Set` source raises the density it covers towards its value (the inflow is
// max(value·coverage − ρ, 0)), an `Add` source adds value·coverage·dt each step. Coverage is 1 inside
// the shape, 0 outside, linear across one cell at the surface. docs/simulation.md states every rule.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "pipeline/physics/grid.h"
#include "runtime/context.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

enum class SourceShape { Sphere = 0, Box = 1, Cylinder = 2 };
enum class InflowMode { Set = 0, Add = 1 };

// One source at one time; lengths in cells, velocity in cells per step.
struct SourceState {
  SourceShape shape = SourceShape::Sphere;
  glm::vec3 centre{0, 0, 0};
  glm::vec3 size{1, 1, 1};                // sphere: radius in [0]; box: half extents; cylinder: radius, half height
  glm::vec3 axis{0, 1, 0};                // cylinder axis (normalised when written)
  InflowMode mode = InflowMode::Set;
  float density = 1.0f;
  float temperature = 0.0f;
  bool setsVelocity = false;
  glm::vec3 velocity{0, 0, 0};
  float noiseAmplitude = 0.0f;            // density varies by ± this fraction
  float noiseScale = 4.0f;                // cells between noise lattice points
  uint32_t noiseSeed = 0;                 // only the low 24 bits are used
  glm::vec3 noiseOffset{0, 0, 0};
};

// Cells [low, high) of a box that holds what some sources cover (empty when low = high).
struct CellBox {
  std::array<int32_t, 3> low{0, 0, 0}, high{0, 0, 0};
};

// The device table of `count` sources (at least one row, so an empty scene binds something valid).
class SourceTable {
 public:
  SourceTable(Context& context, int capacity);
  // Writes the states (at most capacity) into the table; the next recorded or re-submitted step sees them.
  void write(std::span<const SourceState> states);
  const Tensor& table() const { return table_; }
  int count() const { return count_; }
  // Boxes around every source and around the velocity-setting ones: the kernels skip cells outside.
  const CellBox& coverage() const { return coverage_; }
  const CellBox& velocityCoverage() const { return velocityCoverage_; }

 private:
  Tensor table_;
  int capacity_ = 0;
  int count_ = 0;
  CellBox coverage_, velocityCoverage_;
};

// Density and temperature inflow of this step at fluid cells (0 elsewhere). `temperature` and
// `temperatureInflow` may both be null (no temperature field). Only the cells near the sources are
// visited; the rest are zeroed.
void inflowFields(Stream& stream, const Tensor& flags, const Tensor& density, const Tensor* temperature,
                  const SourceTable& sources, float dt, const Tensor& densityInflow, const Tensor* temperatureInflow);

// Blends each velocity-setting source into the faces it covers, in place; only the cells near those
// sources are visited.
void applySourceVelocity(Stream& stream, const Tensor& flags, const SourceTable& sources, const Tensor& velocity);

}  // namespace smokesvd::physics
