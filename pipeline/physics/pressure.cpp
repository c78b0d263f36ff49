#include "pipeline/physics/pressure.h"

#include <algorithm>
#include <array>
#include <string>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::physics {
namespace pressure_ops {
namespace {

// One invocation per cell on a 3D dispatch: 8 lanes along x (the SIMD width of CPU devices), 128 in all.
constexpr std::array<uint32_t, 3> kCellWorkgroup{8, 4, 4};
constexpr uint32_t kScalarWorkgroup = 256;

std::array<uint32_t, 3> cellGroups(const GridSize& grid) {
  auto groups = [](int64_t n, uint32_t size) { return static_cast<uint32_t>((n + size - 1) / size); };
  return {groups(grid.x, kCellWorkgroup[0]), groups(grid.y, kCellWorkgroup[1]), groups(grid.z, kCellWorkgroup[2])};
}

struct GridPush {
  int32_t x, y, z;
};
GridPush push(const GridSize& grid) {
  return {static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
}

// Size and a scalar, then the coarse size: the push block of the multigrid kernels.
struct LevelPush {
  GridPush size;
  float scalar;
  GridPush coarse;
};

template <typename Push>
void dispatchCells(Stream& stream, const char* name, std::vector<int32_t> constants, std::initializer_list<Arg> args,
                   const Push& push, const GridSize& grid) {
  const Kernel& kernel = stream.kernel(std::string("physics/") + name, kCellWorkgroup, std::move(constants));
  stream.dispatch(kernel, args, push, cellGroups(grid));
}

void requirePartials(const Tensor& partials, int64_t needed, const char* what) {
  if (partials.numel() < needed)
    throw Error(std::string(what) + ": the partials buffer holds " + std::to_string(partials.numel()) +
                " floats, " + std::to_string(needed) + " are needed");
}

}  // namespace

int64_t partialCount(const Context& context, const GridSize& grid) {
  const std::array<uint32_t, 3> groups = cellGroups(grid);
  const uint32_t invocations = kCellWorkgroup[0] * kCellWorkgroup[1] * kCellWorkgroup[2];
  const uint32_t subgroup = std::max<uint32_t>(context.info().subgroupSize, 1);
  return int64_t{groups[0]} * groups[1] * groups[2] * ((invocations + subgroup - 1) / subgroup);
}

GridSize coarserGrid(const GridSize& grid) { return {(grid.x + 1) / 2, (grid.y + 1) / 2, (grid.z + 1) / 2}; }

void stencilMasks(Stream& stream, const Tensor& flags, const Tensor& masks) {
  const GridSize grid = volumeGrid(flags, "stencil masks (flags)");
  requireVolume(masks, grid, "stencil masks (masks)");
  dispatchCells(stream, "pressure_stencil", {}, {flags, masks}, push(grid), grid);
}

void residual(Stream& stream, const Tensor& masks, const Tensor& velocity, const Tensor& pressure,
              const Tensor& residual, const Tensor& partials) {
  const GridSize grid = volumeGrid(masks, "pressure residual (masks)");
  requireVector(velocity, grid, "pressure residual (velocity)");
  requireVolume(pressure, grid, "pressure residual (pressure)");
  requireVolume(residual, grid, "pressure residual (residual)");
  const int64_t groups = partialCount(stream.context(), grid);
  requirePartials(partials, 3 * groups, "pressure residual");
  struct { GridPush size; uint32_t count; } p{push(grid), static_cast<uint32_t>(groups)};
  dispatchCells(stream, "pressure_residual", {}, {masks, velocity, pressure, residual, partials}, p, grid);
}

void applyDirection(Stream& stream, const Tensor& masks, const Tensor& preconditioned, const Tensor& directionOld,
                    const Tensor& scalars, const Tensor& direction, const Tensor& product, const Tensor& partials) {
  const GridSize grid = volumeGrid(masks, "pressure direction (masks)");
  for (const Tensor* t : {&preconditioned, &directionOld, &direction, &product})
    requireVolume(*t, grid, "pressure direction");
  requirePartials(partials, partialCount(stream.context(), grid), "pressure direction");
  dispatchCells(stream, "pressure_apply", {},
                {masks, preconditioned, directionOld, scalars, direction, product, partials}, push(grid), grid);
}

void update(Stream& stream, const Tensor& solutionOld, const Tensor& residualOld, const Tensor& direction,
            const Tensor& product, const Tensor& scalars, const Tensor& solution, const Tensor& residual,
            const Tensor& partials) {
  const GridSize grid = volumeGrid(solution, "pressure update (solution)");
  for (const Tensor* t : {&solutionOld, &residualOld, &direction, &product, &residual})
    requireVolume(*t, grid, "pressure update");
  requirePartials(partials, partialCount(stream.context(), grid), "pressure update");
  dispatchCells(stream, "pressure_update", {},
                {solutionOld, residualOld, direction, product, scalars, solution, residual, partials}, push(grid), grid);
}

void scalars(Stream& stream, ScalarStep step, const Tensor& partials, int64_t count, const Tensor& scalars,
             int64_t fluidCells) {
  if (scalars.numel() < kScalarSlots)
    throw Error("pressure scalars: the scalar buffer needs " + std::to_string(kScalarSlots) + " floats");
  requirePartials(partials, step == ScalarStep::Start ? 3 * count : count, "pressure scalars");
  const Kernel& k = stream.kernel("physics/pressure_scalars", {kScalarWorkgroup, 1, 1}, {static_cast<int32_t>(step)});
  struct {
    uint32_t n;
    float inverseFluidCells;
  } p{static_cast<uint32_t>(count), fluidCells > 0 ? 1.0f / static_cast<float>(fluidCells) : 0.0f};
  stream.dispatch(k, {partials, scalars}, p, {1, 1, 1});
}

void removeMean(Stream& stream, const Tensor& masks, const Tensor& residualOld, const Tensor& scalars,
                const Tensor& residual, const Tensor& partials) {
  const GridSize grid = volumeGrid(masks, "pressure mean removal (masks)");
  requireVolume(residualOld, grid, "pressure mean removal (residual)");
  requireVolume(residual, grid, "pressure mean removal (output residual)");
  requirePartials(partials, partialCount(stream.context(), grid), "pressure mean removal");
  dispatchCells(stream, "pressure_remove_mean", {}, {masks, residualOld, scalars, residual, partials}, push(grid), grid);
}

void smooth(Stream& stream, SmoothMode mode, bool dot, const Tensor& masks, const Tensor& rhs, const Tensor& x,
            const Tensor& coarse, const GridSize& coarseGrid, float weight, const Tensor& xNew,
            const Tensor& partials) {
  const GridSize grid = volumeGrid(masks, "multigrid smooth (masks)");
  for (const Tensor* t : {&rhs, &x, &xNew}) requireVolume(*t, grid, "multigrid smooth");
  if (mode == SmoothMode::Corrected) requireVolume(coarse, coarseGrid, "multigrid smooth (coarse correction)");
  if (dot) requirePartials(partials, partialCount(stream.context(), grid), "multigrid smooth");
  dispatchCells(stream, "multigrid_smooth", {static_cast<int32_t>(mode), dot ? 1 : 0},
                {masks, rhs, x, coarse, xNew, partials}, LevelPush{push(grid), weight, push(coarseGrid)}, grid);
}

void restrictResidual(Stream& stream, const Tensor& masks, const Tensor& rhs, const Tensor& x,
                      const Tensor& coarseMasks, float scale, const Tensor& coarseRhs) {
  const GridSize grid = volumeGrid(masks, "multigrid restriction (masks)");
  const GridSize coarse = coarserGrid(grid);
  requireVolume(rhs, grid, "multigrid restriction (rhs)");
  requireVolume(x, grid, "multigrid restriction (x)");
  requireVolume(coarseMasks, coarse, "multigrid restriction (coarse masks)");
  requireVolume(coarseRhs, coarse, "multigrid restriction (coarse rhs)");
  dispatchCells(stream, "multigrid_restrict", {}, {masks, rhs, x, coarseMasks, coarseRhs},
                LevelPush{push(grid), scale, push(coarse)}, coarse);
}

void coarsenFlags(Stream& stream, const Tensor& flags, const Tensor& coarseFlags) {
  const GridSize grid = volumeGrid(flags, "multigrid coarsening (flags)");
  const GridSize coarse = coarserGrid(grid);
  requireVolume(coarseFlags, coarse, "multigrid coarsening (coarse flags)");
  dispatchCells(stream, "multigrid_coarsen", {}, {flags, coarseFlags}, LevelPush{push(grid), 0.0f, push(coarse)},
                coarse);
}

void correctVelocity(Stream& stream, const Tensor& masks, const Tensor& pressure, const Tensor& velocity,
                     const Tensor& velocityOut) {
  const GridSize grid = volumeGrid(masks, "pressure correction (masks)");
  requireVolume(pressure, grid, "pressure correction (pressure)");
  requireVector(velocity, grid, "pressure correction (velocity)");
  requireVector(velocityOut, grid, "pressure correction (output velocity)");
  dispatchCells(stream, "pressure_correct", {}, {masks, pressure, velocity, velocityOut}, push(grid), grid);
}

}  // namespace pressure_ops

using namespace pressure_ops;

namespace {

constexpr int kScalarMaxR = 3, kScalarMaxB = 4;  // slots, as in shaders/physics/pressure_scalars.glsl

}  // namespace

PressureSolver::PressureSolver(Context& context, const Tensor& flags, PressureOptions options)
    : context_(context), grid_(volumeGrid(flags, "pressure solver (flags)")), options_(options) {
  if (options_.smoothingSweeps < 1 || options_.coarsestSweeps < 1 || options_.maxIterations < 1 ||
      options_.tolerance <= 0)
    throw Error("pressure solver: sweeps and iterations must be at least 1 and the tolerance positive");
  const Shape volume = grid_.volume();
  for (int i = 0; i < 2; ++i) {
    solution_[i] = Tensor(context, volume);
    residual_[i] = Tensor(context, volume);
    direction_[i] = Tensor(context, volume);
  }
  product_ = Tensor(context, volume);
  preconditioned_ = Tensor(context, volume);
  partials_ = Tensor(context, {3 * partialCount(context_, grid_)});
  scalars_ = Tensor(context, {kScalarSlots});

  GridSize size = grid_;
  for (;;) {
    Level level{size, Tensor(context, size.volume()), Tensor(context, size.volume()), {},
                Tensor(context, size.volume()), Tensor(context, size.volume()), {}};
    if (!levels_.empty()) {
      level.rhs = Tensor(context, size.volume());
      level.correction = Tensor(context, size.volume());
    }
    levels_.push_back(std::move(level));
    const GridSize next = coarserGrid(size);
    if (std::min({next.x, next.y, next.z}) < options_.coarsestSide || next == size) break;
    size = next;
  }
  setFlags(flags);
}

void PressureSolver::setFlags(const Tensor& flags) {
  requireVolume(flags, grid_, "pressure solver (flags)");
  const std::vector<float> values = flags.download();
  fluidCells_ = std::count_if(values.begin(), values.end(), [](float f) { return (static_cast<uint32_t>(f) & kFluid) != 0; });
  closed_ = std::none_of(values.begin(), values.end(), [](float f) {
    return (static_cast<uint32_t>(f) & (kFluid | kObstacle)) == 0 && (static_cast<uint32_t>(f) & kEmpty) != 0;
  });
  Stream stream(context_);
  stream.copy(flags, levels_[0].flags);
  for (std::size_t l = 1; l < levels_.size(); ++l) coarsenFlags(stream, levels_[l - 1].flags, levels_[l].flags);
  for (const Level& level : levels_) stencilMasks(stream, level.flags, level.masks);
  ops::fill(stream, solution_[0], 0.0f);
  stream.submit();
  for (int parity = 0; parity < 2; ++parity) {
    iteration_[parity] = std::make_unique<Stream>(context_);
    recordIteration(*iteration_[parity], parity);
  }
}

void PressureSolver::setPressure(const Tensor& pressure) {
  requireVolume(pressure, grid_, "pressure solver (initial pressure)");
  Stream stream(context_);
  stream.copy(pressure, solution_[0]);
  stream.submit();
}

void PressureSolver::recordVCycle(Stream& stream, std::size_t level, const Tensor& rhs, const Tensor& out,
                                  bool dot) const {
  const Level& L = levels_[level];
  const bool coarsest = level + 1 == levels_.size();
  const GridSize coarseGrid = coarsest ? L.grid : levels_[level + 1].grid;
  const Tensor& coarse = coarsest ? rhs : levels_[level + 1].correction;
  const float weight = options_.jacobiWeight;
  // A run of sweeps alternating between the level's two buffers, the last one into `last`.
  auto sweeps = [&](int count, SmoothMode firstMode, const Tensor* start, const Tensor& last, bool withDot) {
    const Tensor* x = start ? start : &rhs;
    for (int s = 0; s < count; ++s) {
      const bool final = s + 1 == count;
      const Tensor& target = final ? last : (x == &L.smoothA ? L.smoothB : L.smoothA);
      smooth(stream, s == 0 ? firstMode : SmoothMode::Plain, final && withDot, L.masks, rhs, *x, coarse, coarseGrid,
             weight, target, partials_);
      x = &target;
    }
  };
  if (coarsest) {
    sweeps(options_.coarsestSweeps, SmoothMode::First, nullptr, out, dot);
    return;
  }
  const int nu = options_.smoothingSweeps;
  const Tensor& smoothed = nu % 2 == 1 ? L.smoothA : L.smoothB;
  sweeps(nu, SmoothMode::First, nullptr, smoothed, false);
  const Level& next = levels_[level + 1];
  restrictResidual(stream, L.masks, rhs, smoothed, next.masks, options_.restrictionScale, next.rhs);
  recordVCycle(stream, level + 1, next.rhs, next.correction, false);
  sweeps(nu, SmoothMode::Corrected, &smoothed, out, dot);
}

void PressureSolver::recordIteration(Stream& stream, int parity) const {
  const int next = 1 - parity;
  const int64_t groups = partialCount(context_, grid_);
  const Tensor& masks = levels_[0].masks;
  recordVCycle(stream, 0, residual_[parity], preconditioned_, true);
  scalars(stream, ScalarStep::Direction, partials_, groups, scalars_);
  applyDirection(stream, masks, preconditioned_, direction_[parity], scalars_, direction_[next], product_, partials_);
  scalars(stream, ScalarStep::Step, partials_, groups, scalars_);
  update(stream, solution_[parity], residual_[parity], direction_[next], product_, scalars_, solution_[next],
         residual_[next], partials_);
  scalars(stream, ScalarStep::Residual, partials_, groups, scalars_);
}

PressureReport PressureSolver::start(const Tensor& velocity, bool fromZero) {
  const Tensor& masks = levels_[0].masks;
  const int64_t groups = partialCount(context_, grid_);
  Stream stream(context_);
  if (fromZero) ops::fill(stream, solution_[0], 0.0f);
  ops::fill(stream, direction_[0], 0.0f);
  residual(stream, masks, velocity, solution_[0], residual_[closed_ ? 1 : 0], partials_);
  scalars(stream, ScalarStep::Start, partials_, groups, scalars_, fluidCells_);
  if (closed_) {
    removeMean(stream, masks, residual_[1], scalars_, residual_[0], partials_);
    scalars(stream, ScalarStep::Residual, partials_, groups, scalars_);
  }
  stream.submit();
  const std::vector<float> s = scalars_.download();
  PressureReport report;
  report.initialDivergence = s[kScalarMaxB];
  report.residual = s[kScalarMaxR];
  return report;
}

PressureReport PressureSolver::project(const Tensor& velocity, const Tensor& velocityOut) {
  requireVector(velocity, grid_, "pressure projection (velocity)");
  requireVector(velocityOut, grid_, "pressure projection (output velocity)");
  if (velocity.sharedBuffer() == velocityOut.sharedBuffer())
    throw Error("pressure projection: the output velocity must not alias the input");
  PressureReport report = start(velocity, !options_.warmStart);
  // A previous pressure that fits worse than none (the flow changed completely) is dropped.
  if (options_.warmStart && report.residual > report.initialDivergence) report = start(velocity, true);
  const double target = std::max(options_.tolerance * report.initialDivergence, options_.absoluteTolerance);
  int parity = 0;
  report.converged = report.residual <= target;
  while (!report.converged && report.iterations < options_.maxIterations) {
    iteration_[parity]->submit();
    parity = 1 - parity;
    ++report.iterations;
    report.residual = scalars_.download()[kScalarMaxR];
    report.converged = report.residual <= target;
  }
  report.relativeResidual = report.initialDivergence > 0 ? report.residual / report.initialDivergence : 0;
  Stream finish(context_);
  correctVelocity(finish, levels_[0].masks, solution_[parity], velocity, velocityOut);
  if (parity == 1) finish.copy(solution_[1], solution_[0]);
  finish.submit();
  return report;
}

}  // namespace smokesvd::physics
