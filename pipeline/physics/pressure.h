// Pressure projection: makes a MAC velocity divergence-free, with zero normal velocity at closed walls
// and solid obstacles (Neumann) and p = 0 in empty cells (Dirichlet, open boundaries).
//
// The Poisson equation A p = −div(u) is assembled on the fly from the flags (docs/simulation.md):
//   div(u)_c = Σ_a (u_a(c + e_a) − u_a(c)) over fluid cells c, faces touching an obstacle counted as 0,
//   (A p)_c  = Σ over non-obstacle neighbours n of (p_c − p_n), with p = 0 outside the fluid,
// and solved by conjugate gradients preconditioned with one multigrid V-cycle (MGPCG): damped Jacobi
// smoothing, piecewise-constant transfers between levels, coarse flags from the 2×2×2 children. The
// solve stops when max |r| ≤ max(tolerance · max |div u|, absoluteTolerance) over the fluid; since the
// divergence left after the projection is −r, that is also the bound on max |div u| afterwards. In a
// closed domain (no empty cell) the matrix is singular and the mean of the initial residual is removed.
// Every iteration runs on the device from scalars kept in a small buffer; the host reads max |r| after
// each one. The solver's vectors use a padded layout [D, H, P], P = W rounded up to a multiple of 4, so
// its inner kernels work on blocks of four cells read as vec4 texels (shaders/physics/multigrid_blocks.glsl).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "pipeline/physics/grid.h"
#include "runtime/context.h"
#include "runtime/stream.h"
#include "runtime/tensor.h"

namespace smokesvd::physics {

struct PressureOptions {
  double tolerance = 1e-4;          // relative residual in the max norm: max |r| / max |div u|
  double absoluteTolerance = 1e-6;  // ... or this max |r| (float rounding floor for nearly divergence-free input)
  int maxIterations = 100;          // conjugate-gradient iterations before giving up (report says so)
  bool warmStart = true;            // start from the previous solve's pressure
  int smoothingSweeps = 2;          // Jacobi sweeps before and after each coarse correction
  int coarsestSweeps = 16;          // Jacobi sweeps on the coarsest level
  float jacobiWeight = 0.9f;        // ω of the damped Jacobi sweeps (< 1 keeps the V-cycle positive definite)
  float restrictionScale = 0.5f;    // γ: coarse rhs = γ · sum of the 8 children's residuals
  int64_t coarsestSide = 4;         // stop coarsening when a side would fall below this
};

struct PressureReport {
  int iterations = 0;             // conjugate-gradient iterations run
  double initialDivergence = 0;   // max |div u| over fluid cells before the projection
  double residual = 0;            // max |r| at the end: max |div u| left after the projection
  double relativeResidual = 0;    // residual / initialDivergence (0 when there was nothing to remove)
  bool converged = false;         // never when !finite
  bool finite = true;             // false when the velocity or the solve held NaN or infinity
};

class PressureSolver {
 public:
  // `flags` [D, H, W] (1 fluid, 2 obstacle, 4 empty) are copied into the solver's multigrid hierarchy.
  PressureSolver(Context& context, const Tensor& flags, PressureOptions options = {});
  PressureSolver(const PressureSolver&) = delete;
  PressureSolver& operator=(const PressureSolver&) = delete;

  // velocityOut = velocity − ∇p (MAC, [3, D, H, W]); faces touching an obstacle become 0. Both must be
  // distinct tensors of the solver's grid. Submits its own streams: record earlier work and submit it first.
  PressureReport project(const Tensor& velocity, const Tensor& velocityOut);

  // New obstacles or open sides: rebuilds the multigrid flags and forgets the previous pressure.
  void setFlags(const Tensor& flags);
  // The pressure of the last solve, [D, H, W] values (0 outside the fluid); the next solve starts from it.
  std::vector<float> pressure() const;
  // Sets the pressure the next solve starts from (a checkpoint's), [D, H, W] values.
  void setPressure(const std::vector<float>& pressure);

  const GridSize& grid() const { return grid_; }
  const PressureOptions& options() const { return options_; }
  int levels() const { return static_cast<int>(levels_.size()); }

 private:
  struct Level {
    GridSize grid, padded;
    Tensor flags;                                    // [D, H, W]
    Tensor masks, rhs, smoothA, smoothB, scratch, correction;  // padded
  };
  void recordVCycle(Stream& stream, std::size_t level, const Tensor& rhs, const Tensor& out, bool dot) const;
  void recordIteration(Stream& stream, int parity) const;
  // Initial residual from solution_[0] (or zero): report with initialDivergence and residual set.
  PressureReport start(const Tensor& velocity, bool fromZero);

  Context& context_;
  GridSize grid_, padded_;
  PressureOptions options_;
  std::vector<Level> levels_;
  int64_t fluidCells_ = 0;
  bool closed_ = false;  // no empty cell: the constants are the matrix's null space
  Tensor solution_[2], residual_[2], direction_[2], product_, preconditioned_, partials_, scalars_;
  std::unique_ptr<Stream> iteration_[2];
};

// The building blocks, one dispatch each (the solver composes them; tests check each against a CPU
// reference). "Padded" tensors are [D, H, P] with P = W rounded up to a multiple of 4 and hold 0 in the
// padding and outside the fluid; the block kernels rely on that. Stencil kernels read stencil masks (one
// per cell: fluid and non-obstacle bits of the cell and its six neighbours; obstacle_flags.glsl) rather
// than flags. Partial buffers hold one value per subgroup (pressure_partials.glsl): startPartialCount
// floats per set for residual() (three sets), partialCount for the block kernels. Scalar slots are listed
// in shaders/physics/pressure_scalars.glsl.
namespace pressure_ops {

enum class ScalarStep { Start = 0, Direction = 1, Step = 2, Residual = 3 };
constexpr int kScalarSlots = 8;

GridSize paddedGrid(const GridSize& grid);
GridSize coarserGrid(const GridSize& grid);
int64_t startPartialCount(const Context& context, const GridSize& grid);  // residual()
int64_t partialCount(const Context& context, const GridSize& grid);       // block kernels of the padded grid

// masks (padded) from flags [D, H, W].
void stencilMasks(Stream& stream, const Tensor& flags, const Tensor& masks);
// residual = −div(velocity) − A·pressure at fluid cells; partials: max |b|, max |residual|, Σ residual.
void residual(Stream& stream, const Tensor& masks, const Tensor& velocity, const Tensor& pressure,
              const Tensor& residual, const Tensor& partials);
// direction = z + β·directionOld, product = A·direction (fluid), partials = Σ direction·product.
void applyDirection(Stream& stream, const Tensor& masks, const Tensor& preconditioned, const Tensor& directionOld,
                    const Tensor& scalars, const Tensor& direction, const Tensor& product, const Tensor& partials);
// solution = solutionOld + α·direction, residual = residualOld − α·product, partials = max |residual|.
void update(Stream& stream, const Tensor& solutionOld, const Tensor& residualOld, const Tensor& direction,
            const Tensor& product, const Tensor& scalars, const Tensor& solution, const Tensor& residual,
            const Tensor& partials);
// Reduces `count` partials per set into the scalar buffer (ScalarStep says which); the Start step also
// takes the mean of the residual over `fluidCells`.
void scalars(Stream& stream, ScalarStep step, const Tensor& partials, int64_t count, const Tensor& scalars,
             int64_t fluidCells = 0);
// residual = residualOld − mean (the scalar buffer's) at fluid cells; partials: max |residual|.
void removeMean(Stream& stream, const Tensor& masks, const Tensor& residualOld, const Tensor& scalars,
                const Tensor& residual, const Tensor& partials);
// One damped Jacobi sweep (from x = 0 if `first`; x is then unread); partials (Σ rhs·xNew) only if `dot`.
void smooth(Stream& stream, bool first, bool dot, const Tensor& masks, const Tensor& rhs, const Tensor& x,
            float weight, const Tensor& xNew, const Tensor& partials);
// residual = rhs − A x at fluid cells.
void levelResidual(Stream& stream, const Tensor& masks, const Tensor& rhs, const Tensor& x, const Tensor& residual);
// coarseRhs = scale · Σ of the 8 children's residuals at fluid coarse cells.
void restrictResidual(Stream& stream, const Tensor& residual, const Tensor& coarseMasks, float scale,
                      const Tensor& coarseRhs);
// xNew = x + coarse(parent) at fluid cells.
void prolong(Stream& stream, const Tensor& masks, const Tensor& x, const Tensor& coarse, const Tensor& xNew);
// Flags [D, H, W] of the next coarser level.
void coarsenFlags(Stream& stream, const Tensor& flags, const Tensor& coarseFlags);
// velocityOut = velocity − ∇pressure on faces next to fluid, 0 on faces touching an obstacle.
void correctVelocity(Stream& stream, const Tensor& masks, const Tensor& pressure, const Tensor& velocity,
                     const Tensor& velocityOut);

}  // namespace pressure_ops

}  // namespace smokesvd::physics
