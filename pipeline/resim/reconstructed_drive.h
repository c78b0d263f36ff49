// The reconstruction as the inputs that drive a re-simulation (docs/applications.md). With T reconstructed
// frames, U the upsampling to the re-simulation's grid (pipeline/resim/upsample.h), P the projection onto
// the reconstruction's own domain (its walls and open top, no edits) and A the advection:
//   G_t = U(velocity_t), t = 0 .. T-2        (velocity_(T-1) repeats velocity_(T-2) in the files; unused)
//   force F_t = P G_(t+1) - A(P G_t, P G_t)  for t = 0 .. T-3: what turns the self-advected reconstructed
//                                            flow into the next reconstructed one (its buoyancy and whatever
//                                            else moved the real smoke), a MAC acceleration
//   inflow I_t = s U(inflow_t)               for t = 1 .. T-1 (s = --inflow-scale; frame 0's inflow is its
//                                            whole density, not a source)
// Past the reconstruction, F and I are the means of their last (up to) kMeanWindow frames, so the plume
// keeps being fed and driven as it was at the end of the video. The simulator then runs
//   v_(t+1) = P_edit(A(v_t, v_t) + edits + F_t),   rho_(t+1) = A(rho_t, v_t) + I_(t+1)
// from v_0 = P_edit G_0: without edits P_edit = P, and v_t = P G_t for every reconstructed frame, so the
// re-simulation departs from the reconstruction only by the part of its velocity that P removes.
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/physics/grid.h"
#include "pipeline/physics/pressure.h"
#include "pipeline/sim/saved_run.h"
#include "runtime/context.h"
#include "runtime/tensor.h"

namespace smokesvd::resim {

constexpr int kMeanWindow = 8;

struct StepInputs {
  Tensor inflow;  // [D, H, W], undefined when there is none
  Tensor force;   // MAC [3, D, H, W], undefined when there is none
};

class ReconstructedDrive {
 public:
  ReconstructedDrive(Context& context, const sim::SavedRun& reconstruction, int upres, double inflowScale);

  const GridSize& grid() const { return grid_; }
  std::vector<float> initialDensity() const;   // U(density_0), host values
  std::vector<float> initialVelocity() const;  // G_0 (not projected; zeros for a one-frame clip)
  // The inputs of the step from frame t to t + 1; t = 0, 1, 2, ... in turn.
  StepInputs next();
  // The frames each input comes from and the part of each reconstructed velocity the projection removed
  // (||G_t - P G_t|| / ||G_t||, the cause of any departure from the reconstruction), for run.json.
  nlohmann::json describe() const;
  const std::vector<double>& removedByProjection() const { return removed_; }

 private:
  Tensor upsampledVelocity(int frame) const;  // G_frame
  Tensor projected(const Tensor& velocity);   // P velocity; records ||velocity - P velocity|| / ||velocity||
  Tensor forceAt(int t);                      // F_t from P G_t (previous_) and P G_(t+1)
  struct Window {
    int first = 0, last = -1;  // frames averaged, inclusive; empty when last < first
    int count() const { return std::max(last - first + 1, 0); }
  };

  Context& context_;
  const sim::SavedRun& reconstruction_;
  int upres_;
  float inflowScale_;
  GridSize grid_;
  Tensor flags_;
  std::unique_ptr<physics::FlagGrid> flagGrid_;
  std::unique_ptr<physics::PressureSolver> solver_;
  int step_ = 0;
  Tensor previous_;                  // P G_step
  Window forceWindow_, inflowWindow_;
  Tensor forceSum_, inflowSum_;      // sums over the windows, then (once past them) the means
  bool forceMean_ = false, inflowMean_ = false;
  std::vector<double> removed_;      // per reconstructed velocity: the fraction (L2) P removes
};

}  // namespace smokesvd::resim
