// The smoke simulator: one step is
//   inflow (the sources' density and temperature for this step) → advection of density, temperature
//   and the MAC velocity (adding the inflow) → forces (buoyancy, wind, vorticity confinement, force
//   fields) → velocity of the sources that set it → pressure projection,
// so that every saved frame obeys density_next = A(density, velocity) + inflow exactly (one step per
// frame). A frame is scene.stepsPerFrame steps; the inflow of a frame is the sum over its steps.
// Where an obstacle appears or vanishes the domain changes before the frame's first step: density and
// temperature inside obstacles are removed and the velocity is projected onto the new flags, so the
// relation then holds for the previous frame's fields as the new domain holds them (enforceDomain()).
// Re-simulation (pipeline/resim) adds two inputs of its own: an inflow field and a MAC acceleration.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "pipeline/physics/forces.h"
#include "pipeline/physics/pressure.h"
#include "pipeline/physics/sources.h"
#include "pipeline/sim/scene.h"
#include "runtime/context.h"
#include "runtime/tensor.h"

namespace smokesvd::sim {

// How a run that became non-finite is explained (with the frame and the field) and what to change.
extern const char* const kBlownUp;

struct FrameReport {
  int frame = 0;                  // the frame just completed
  int pressureIterations = 0;     // summed over the frame's steps
  double relativeResidual = 0;    // the largest over the frame's steps
  double maxDivergence = 0;       // max |div u| left after the last projection
  bool converged = true;          // every projection reached the tolerance
};

// Everything a run needs to continue exactly where it stopped (host copies).
struct SimulatorState {
  int frame = 0;                                // frames completed
  std::vector<float> density, temperature, velocity, pressure;
};

class Simulator {
 public:
  Simulator(Context& context, const Scene& scene);

  // Runs the next frame's steps.
  FrameReport advanceFrame();
  int frame() const { return frame_; }  // frames completed
  const Scene& scene() const { return scene_; }
  const GridSize& grid() const { return grid_; }

  const Tensor& flags() const { return flags_; }
  const Tensor& density() const { return density_; }             // [D, H, W]
  const Tensor& velocity() const { return velocity_; }           // MAC [3, D, H, W]
  const Tensor& inflow() const { return frameInflow_; }          // density inflow of the last frame
  const Tensor* temperature() const { return temperature_.defined() ? &temperature_ : nullptr; }

  SimulatorState state() const;
  void restore(const SimulatorState& state);

  // Inputs kept from frame to frame until replaced (an undefined Tensor removes one):
  //   inflow [D, H, W]: density added in every frame besides the sources' (spread evenly over the frame's
  //     steps), at fluid cells only;
  //   force, MAC [3, D, H, W]: an acceleration added to every face after the other forces, before the
  //     projection (which zeroes the faces touching obstacles).
  void setExternalInflow(Tensor inflow);
  void setExternalForce(Tensor acceleration);
  // Fits the state to the current flags: density and temperature are 0 in obstacle cells, and the velocity
  // is projected (divergence-free, no flow through walls and obstacles). Runs where obstacles change and
  // after restoring a state that did not come from this scene (a re-simulation's start).
  physics::PressureReport enforceDomain();

 private:
  physics::PressureReport step(int substep);
  std::vector<physics::SourceState> sourceStates(double time) const;
  physics::Buoyancy buoyancyAt(double time) const;
  void updateFlags(int frame);

  Context& context_;
  Scene scene_;
  GridSize grid_;
  int frame_ = 0;
  Tensor flags_, density_, densityNext_, temperature_, temperatureNext_, velocity_, velocityScratch_[2];
  Tensor densityInflow_, temperatureInflow_, frameInflow_, vorticity_;
  Tensor openMask_;                      // 1 at cells that are not obstacles, else 0
  Tensor fluidMask_;                     // 1 at fluid cells, else 0
  Tensor externalInflow_, externalForce_;
  std::vector<Tensor> forceFields_;
  std::unique_ptr<physics::FlagGrid> flagGrid_;  // the flags with the advection's masks
  physics::SourceTable sources_;
  std::unique_ptr<physics::PressureSolver> solver_;
};

}  // namespace smokesvd::sim
