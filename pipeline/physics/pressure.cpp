#include "pipeline/physics/pressure.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <string>

#include "nets/ops/elementwise.h"
#include "runtime/error.h"

namespace smokesvd::physics {
namespace pressure_ops {
namespace {

// 8 lanes along x (the SIMD width of CPU devices), 128 invocations in all.
constexpr std::array<uint32_t, 3> kWorkgroup{8, 4, 4};

struct GridPush {
  int32_t x, y, z;
};
GridPush push(const GridSize& grid) {
  return {static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
}
// The block grid of a padded level: four cells along x per invocation.
GridPush blocks(const GridSize& padded) { return {static_cast<int32_t>(padded.x / 4), static_cast<int32_t>(padded.y),
                                                  static_cast<int32_t>(padded.z)}; }

std::array<uint32_t, 3> groups(const GridPush& items) {
  auto count = [](int32_t n, uint32_t size) { return (static_cast<uint32_t>(n) + size - 1) / size; };
  return {count(items.x, kWorkgroup[0]), count(items.y, kWorkgroup[1]), count(items.z, kWorkgroup[2])};
}

int64_t subgroupSlots(const Context& context, const GridPush& items) {
  const std::array<uint32_t, 3> g = groups(items);
  const uint32_t invocations = kWorkgroup[0] * kWorkgroup[1] * kWorkgroup[2];
  const uint32_t subgroup = std::max<uint32_t>(context.info().subgroupSize, 1);
  return int64_t{g[0]} * g[1] * g[2] * ((invocations + subgroup - 1) / subgroup);
}

// Runs `name` with one invocation per item of `items` (cells or blocks).
template <typename Push>
void dispatch(Stream& stream, const char* name, std::vector<int32_t> constants, std::initializer_list<Arg> args,
              const Push& push, const GridPush& items) {
  const Kernel& kernel = stream.kernel(std::string("physics/") + name, kWorkgroup, std::move(constants));
  stream.dispatch(kernel, args, push, groups(items));
}

// The grid of a padded tensor, after checking that its width is a multiple of 4.
GridSize paddedOf(const Tensor& tensor, const char* what) {
  const GridSize grid = volumeGrid(tensor, what);
  if (grid.x % 4 != 0)
    throw Error(std::string(what) + ": a padded volume's width must be a multiple of 4, got " + toString(tensor.shape()));
  return grid;
}

void requirePartials(const Tensor& partials, int64_t needed, const char* what) {
  if (partials.numel() < needed)
    throw Error(std::string(what) + ": the partials buffer holds " + std::to_string(partials.numel()) +
                " floats, " + std::to_string(needed) + " are needed");
}

// A real grid and its padded tensor agree.
void requirePaddedOf(const Tensor& tensor, const GridSize& grid, const char* what) {
  requireVolume(tensor, paddedGrid(grid), what);
}

}  // namespace

GridSize paddedGrid(const GridSize& grid) { return {.x = (grid.x + 3) / 4 * 4, .y = grid.y, .z = grid.z}; }

GridSize coarserGrid(const GridSize& grid) {
  return {.x = (grid.x + 1) / 2, .y = (grid.y + 1) / 2, .z = (grid.z + 1) / 2};
}

namespace {

// Widths that are a multiple of 4 need no padding: the kernels that meet the user's layout (the first
// residual, the velocity correction) then also work on blocks.
bool aligned(const GridSize& grid) { return grid.x % 4 == 0; }

}  // namespace

int64_t startPartialCount(const Context& context, const GridSize& grid) {
  return aligned(grid) ? partialCount(context, grid) : subgroupSlots(context, push(grid));
}

int64_t partialCount(const Context& context, const GridSize& grid) {
  return subgroupSlots(context, blocks(paddedGrid(grid)));
}

void stencilMasks(Stream& stream, const Tensor& flags, const Tensor& masks) {
  const GridSize grid = volumeGrid(flags, "stencil masks (flags)");
  requirePaddedOf(masks, grid, "stencil masks (masks)");
  const GridSize padded = paddedGrid(grid);
  struct {
    GridPush size;
    int32_t width;
  } p{push(grid), static_cast<int32_t>(padded.x)};
  dispatch(stream, "pressure_stencil", {}, {flags, masks}, p, push(padded));
}

void residual(Stream& stream, const Tensor& masks, const Tensor& velocity, const Tensor& pressure,
              const Tensor& residual, const Tensor& partials) {
  const GridSize grid = vectorGrid(velocity, "pressure residual (velocity)");
  requirePaddedOf(masks, grid, "pressure residual (masks)");
  requirePaddedOf(pressure, grid, "pressure residual (pressure)");
  requirePaddedOf(residual, grid, "pressure residual (residual)");
  const int64_t count = startPartialCount(stream.context(), grid);
  requirePartials(partials, 3 * count, "pressure residual");
  if (aligned(grid)) {
    struct {
      GridPush blocks;
      uint32_t count;
    } p{blocks(grid), static_cast<uint32_t>(count)};
    dispatch(stream, "pressure_residual_blocks", {},
             {asVec4(masks), asVec4(velocity), asVec4(pressure), residual, partials}, p, blocks(grid));
    return;
  }
  struct {
    GridPush size;
    int32_t width;
    uint32_t count;
  } p{push(grid), static_cast<int32_t>(paddedGrid(grid).x), static_cast<uint32_t>(count)};
  dispatch(stream, "pressure_residual", {}, {masks, velocity, pressure, residual, partials}, p, push(grid));
}

void applyDirection(Stream& stream, const Tensor& masks, const Tensor& preconditioned, const Tensor& directionOld,
                    const Tensor& scalars, const Tensor& direction, const Tensor& product, const Tensor& partials) {
  const GridSize padded = paddedOf(masks, "pressure direction (masks)");
  for (const Tensor* t : {&preconditioned, &directionOld, &direction, &product})
    requireVolume(*t, padded, "pressure direction");
  requirePartials(partials, subgroupSlots(stream.context(), blocks(padded)), "pressure direction");
  dispatch(stream, "pressure_apply", {}, {asVec4(masks), asVec4(preconditioned), asVec4(directionOld), scalars, direction, product, partials},
           blocks(padded), blocks(padded));
}

void update(Stream& stream, const Tensor& solutionOld, const Tensor& residualOld, const Tensor& direction,
            const Tensor& product, const Tensor& scalars, const Tensor& solution, const Tensor& residual,
            const Tensor& partials) {
  const GridSize padded = paddedOf(solution, "pressure update (solution)");
  for (const Tensor* t : {&solutionOld, &residualOld, &direction, &product, &residual})
    requireVolume(*t, padded, "pressure update");
  requirePartials(partials, subgroupSlots(stream.context(), blocks(padded)), "pressure update");
  dispatch(stream, "pressure_update", {},
           {asVec4(solutionOld), asVec4(residualOld), asVec4(direction), asVec4(product), scalars, solution, residual,
            partials}, blocks(padded),
           blocks(padded));
}

void scalars(Stream& stream, ScalarStep step, const Tensor& partials, int64_t count, const Tensor& scalars,
             int64_t fluidCells) {
  if (scalars.numel() < kScalarSlots)
    throw Error("pressure scalars: the scalar buffer needs " + std::to_string(kScalarSlots) + " floats");
  requirePartials(partials, step == ScalarStep::Start ? 3 * count : count, "pressure scalars");
  // One workgroup of one subgroup (DeviceInfo::reductionWorkgroup) reduces every partial.
  const Kernel& k = stream.kernel("physics/pressure_scalars", {stream.context().info().reductionWorkgroup(), 1, 1},
                                  {static_cast<int32_t>(step)});
  struct {
    uint32_t n;
    float inverseFluidCells;
  } p{static_cast<uint32_t>(count), fluidCells > 0 ? 1.0f / static_cast<float>(fluidCells) : 0.0f};
  stream.dispatch(k, {partials, scalars}, p, {1, 1, 1});
}

void removeMean(Stream& stream, const Tensor& masks, const Tensor& residualOld, const Tensor& scalars,
                const Tensor& residual, const Tensor& partials) {
  const GridSize padded = paddedOf(masks, "pressure mean removal (masks)");
  requireVolume(residualOld, padded, "pressure mean removal (residual)");
  requireVolume(residual, padded, "pressure mean removal (output residual)");
  requirePartials(partials, subgroupSlots(stream.context(), blocks(padded)), "pressure mean removal");
  dispatch(stream, "pressure_remove_mean", {}, {asVec4(masks), asVec4(residualOld), scalars, residual, partials}, blocks(padded),
           blocks(padded));
}

void smooth(Stream& stream, bool first, bool dot, const Tensor& masks, const Tensor& rhs, const Tensor& x, float weight,
            const Tensor& xNew, const Tensor& partials) {
  const GridSize padded = paddedOf(masks, "multigrid smooth (masks)");
  for (const Tensor* t : {&rhs, &x, &xNew}) requireVolume(*t, padded, "multigrid smooth");
  if (dot) requirePartials(partials, subgroupSlots(stream.context(), blocks(padded)), "multigrid smooth");
  struct {
    GridPush blocks;
    float omega;
  } p{blocks(padded), weight};
  dispatch(stream, "multigrid_smooth", {first ? 1 : 0, dot ? 1 : 0}, {asVec4(masks), asVec4(rhs), asVec4(x), xNew, partials}, p,
           blocks(padded));
}

void levelResidual(Stream& stream, const Tensor& masks, const Tensor& rhs, const Tensor& x, const Tensor& residual) {
  const GridSize padded = paddedOf(masks, "multigrid residual (masks)");
  for (const Tensor* t : {&rhs, &x, &residual}) requireVolume(*t, padded, "multigrid residual");
  dispatch(stream, "multigrid_residual", {}, {asVec4(masks), asVec4(rhs), asVec4(x), residual}, blocks(padded), blocks(padded));
}

void restrictResidual(Stream& stream, const Tensor& residual, const Tensor& coarseMasks, float scale,
                      const Tensor& coarseRhs) {
  const GridSize fine = paddedOf(residual, "multigrid restriction (residual)");
  const GridSize coarse = paddedOf(coarseMasks, "multigrid restriction (coarse masks)");
  requireVolume(coarseRhs, coarse, "multigrid restriction (coarse rhs)");
  if (2 * coarse.x < fine.x || coarse.y != (fine.y + 1) / 2 || coarse.z != (fine.z + 1) / 2)
    throw Error("multigrid restriction: " + toString(coarseMasks.shape()) + " is not the coarser level of " +
                toString(residual.shape()));
  struct {
    GridPush fine;
    float gamma;
    GridPush coarse;
  } p{blocks(fine), scale, blocks(coarse)};
  dispatch(stream, "multigrid_restrict", {}, {asVec4(residual), asVec4(coarseMasks), coarseRhs}, p, blocks(coarse));
}

void prolong(Stream& stream, const Tensor& masks, const Tensor& x, const Tensor& coarse, const Tensor& xNew) {
  const GridSize padded = paddedOf(masks, "multigrid prolongation (masks)");
  const GridSize coarseGrid = paddedOf(coarse, "multigrid prolongation (coarse)");
  requireVolume(x, padded, "multigrid prolongation (x)");
  requireVolume(xNew, padded, "multigrid prolongation (output)");
  struct {
    GridPush fine;
    int32_t unused;
    GridPush coarse;
  } p{blocks(padded), 0, blocks(coarseGrid)};
  dispatch(stream, "multigrid_prolong", {}, {asVec4(masks), asVec4(x), asVec4(coarse), xNew}, p, blocks(padded));
}

void coarsenFlags(Stream& stream, const Tensor& flags, const Tensor& coarseFlags) {
  const GridSize grid = volumeGrid(flags, "multigrid coarsening (flags)");
  const GridSize coarse = coarserGrid(grid);
  requireVolume(coarseFlags, coarse, "multigrid coarsening (coarse flags)");
  struct {
    GridPush fine;
    int32_t unused;
    GridPush coarse;
  } p{push(grid), 0, push(coarse)};
  dispatch(stream, "multigrid_coarsen", {}, {flags, coarseFlags}, p, push(coarse));
}

void correctVelocity(Stream& stream, const Tensor& masks, const Tensor& pressure, const Tensor& velocity,
                     const Tensor& velocityOut) {
  const GridSize grid = vectorGrid(velocity, "pressure correction (velocity)");
  requirePaddedOf(masks, grid, "pressure correction (masks)");
  requirePaddedOf(pressure, grid, "pressure correction (pressure)");
  requireVector(velocityOut, grid, "pressure correction (output velocity)");
  if (aligned(grid)) {
    dispatch(stream, "pressure_correct_blocks", {}, {asVec4(masks), asVec4(pressure), asVec4(velocity), velocityOut},
             blocks(grid), blocks(grid));
    return;
  }
  struct {
    GridPush size;
    int32_t width;
  } p{push(grid), static_cast<int32_t>(paddedGrid(grid).x)};
  dispatch(stream, "pressure_correct", {}, {masks, pressure, velocity, velocityOut}, p, push(grid));
}

}  // namespace pressure_ops

using namespace pressure_ops;

namespace {

// Slots, as in shaders/physics/pressure_scalars.glsl.
constexpr int kScalarRz = 0, kScalarMaxR = 3, kScalarMaxB = 4, kScalarMeanR = 6;

// GPU max() may drop a NaN, so sums, which keep it, are checked too: r·z, and the mean of r at the start.
bool finiteScalars(const std::vector<float>& s, std::initializer_list<int> slots) {
  for (int slot : slots)
    if (!std::isfinite(s[static_cast<std::size_t>(slot)])) return false;
  return true;
}

}  // namespace

PressureSolver::PressureSolver(Context& context, const Tensor& flags, PressureOptions options)
    : context_(context),
      grid_(volumeGrid(flags, "pressure solver (flags)")),
      padded_(paddedGrid(grid_)),
      options_(options) {
  if (options_.smoothingSweeps < 1 || options_.coarsestSweeps < 1 || options_.maxIterations < 1 ||
      options_.tolerance <= 0)
    throw Error("pressure solver: sweeps and iterations must be at least 1 and the tolerance positive");
  const Shape volume = padded_.volume();
  Stream zero(context);
  auto zeroed = [&](const Shape& shape) {
    Tensor t(context, shape);
    ops::fill(zero, t, 0.0f);
    return t;
  };
  for (int i = 0; i < 2; ++i) {
    solution_[i] = zeroed(volume);
    residual_[i] = zeroed(volume);
    direction_[i] = zeroed(volume);
  }
  product_ = zeroed(volume);
  preconditioned_ = zeroed(volume);
  partials_ = Tensor(context, {3 * std::max(startPartialCount(context, grid_), partialCount(context, grid_))});
  scalars_ = Tensor(context, {kScalarSlots});

  GridSize size = grid_;
  for (;;) {
    const GridSize padded = paddedGrid(size);
    Level level{size, padded, Tensor(context, size.volume()), zeroed(padded.volume()), {}, zeroed(padded.volume()),
                zeroed(padded.volume()), zeroed(padded.volume()), {}};
    if (!levels_.empty()) {
      level.rhs = zeroed(padded.volume());
      level.correction = zeroed(padded.volume());
    }
    levels_.push_back(std::move(level));
    const GridSize next = coarserGrid(size);
    if (std::min({next.x, next.y, next.z}) < options_.coarsestSide || next == size) break;
    size = next;
  }
  zero.submit();
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

std::vector<float> PressureSolver::pressure() const {
  const std::vector<float> padded = solution_[0].download();
  std::vector<float> values(static_cast<std::size_t>(grid_.cells()));
  for (int64_t row = 0; row < grid_.y * grid_.z; ++row)
    std::copy_n(padded.begin() + row * padded_.x, grid_.x, values.begin() + row * grid_.x);
  return values;
}

void PressureSolver::setPressure(const std::vector<float>& values) {
  if (static_cast<int64_t>(values.size()) != grid_.cells())
    throw Error("pressure solver: the initial pressure has " + std::to_string(values.size()) + " values, the grid " +
                std::to_string(grid_.cells()));
  std::vector<float> padded(static_cast<std::size_t>(padded_.cells()), 0.0f);
  for (int64_t row = 0; row < grid_.y * grid_.z; ++row)
    std::copy_n(values.begin() + row * grid_.x, grid_.x, padded.begin() + row * padded_.x);
  solution_[0].upload(padded);
}

void PressureSolver::recordVCycle(Stream& stream, std::size_t level, const Tensor& rhs, const Tensor& out,
                                  bool dot) const {
  const Level& L = levels_[level];
  const float weight = options_.jacobiWeight;
  // `count` Jacobi sweeps from `start` (null: from zero), alternating between the level's two buffers,
  // the last one into `last`.
  auto sweeps = [&](int count, const Tensor* start, const Tensor& last, bool withDot) {
    const Tensor* x = start;
    for (int s = 0; s < count; ++s) {
      const bool final = s + 1 == count;
      const Tensor& target = final ? last : (x == &L.smoothA ? L.smoothB : L.smoothA);
      smooth(stream, x == nullptr, final && withDot, L.masks, rhs, x ? *x : rhs, weight, target, partials_);
      x = &target;
    }
  };
  if (level + 1 == levels_.size()) {
    sweeps(options_.coarsestSweeps, nullptr, out, dot);
    return;
  }
  const int nu = options_.smoothingSweeps;
  const Tensor& smoothed = nu % 2 == 1 ? L.smoothA : L.smoothB;
  const Tensor& corrected = nu % 2 == 1 ? L.smoothB : L.smoothA;
  const Level& next = levels_[level + 1];
  sweeps(nu, nullptr, smoothed, false);
  levelResidual(stream, L.masks, rhs, smoothed, L.scratch);
  restrictResidual(stream, L.scratch, next.masks, options_.restrictionScale, next.rhs);
  recordVCycle(stream, level + 1, next.rhs, next.correction, false);
  prolong(stream, L.masks, smoothed, next.correction, corrected);
  sweeps(nu, &corrected, out, dot);
}

void PressureSolver::recordIteration(Stream& stream, int parity) const {
  const int next = 1 - parity;
  const int64_t count = partialCount(context_, grid_);
  const Tensor& masks = levels_[0].masks;
  recordVCycle(stream, 0, residual_[parity], preconditioned_, true);
  scalars(stream, ScalarStep::Direction, partials_, count, scalars_);
  applyDirection(stream, masks, preconditioned_, direction_[parity], scalars_, direction_[next], product_, partials_);
  scalars(stream, ScalarStep::Step, partials_, count, scalars_);
  update(stream, solution_[parity], residual_[parity], direction_[next], product_, scalars_, solution_[next],
         residual_[next], partials_);
  scalars(stream, ScalarStep::Residual, partials_, count, scalars_);
}

PressureReport PressureSolver::start(const Tensor& velocity, bool fromZero) {
  const Tensor& masks = levels_[0].masks;
  Stream stream(context_);
  if (fromZero) ops::fill(stream, solution_[0], 0.0f);
  ops::fill(stream, direction_[0], 0.0f);
  residual(stream, masks, velocity, solution_[0], residual_[closed_ ? 1 : 0], partials_);
  scalars(stream, ScalarStep::Start, partials_, startPartialCount(context_, grid_), scalars_, fluidCells_);
  if (closed_) {
    removeMean(stream, masks, residual_[1], scalars_, residual_[0], partials_);
    scalars(stream, ScalarStep::Residual, partials_, partialCount(context_, grid_), scalars_);
  }
  stream.submit();
  const std::vector<float> s = scalars_.download();
  PressureReport report;
  report.initialDivergence = s[kScalarMaxB];
  report.residual = s[kScalarMaxR];
  report.finite = finiteScalars(s, {kScalarMaxB, kScalarMaxR, kScalarMeanR});
  return report;
}

PressureReport PressureSolver::project(const Tensor& velocity, const Tensor& velocityOut) {
  requireVector(velocity, grid_, "pressure projection (velocity)");
  requireVector(velocityOut, grid_, "pressure projection (output velocity)");
  if (velocity.sharedBuffer() == velocityOut.sharedBuffer())
    throw Error("pressure projection: the output velocity must not alias the input");
  PressureReport report = start(velocity, !options_.warmStart);
  // A previous pressure that fits worse than none (the flow changed completely) is dropped.
  if (options_.warmStart && (report.residual > report.initialDivergence || !report.finite)) report = start(velocity, true);
  const double target = std::max(options_.tolerance * report.initialDivergence, options_.absoluteTolerance);
  int parity = 0;
  report.converged = report.finite && report.residual <= target;
  while (report.finite && !report.converged && report.iterations < options_.maxIterations) {
    iteration_[parity]->submit();
    parity = 1 - parity;
    ++report.iterations;
    const std::vector<float> s = scalars_.download();
    report.residual = s[kScalarMaxR];
    report.finite = finiteScalars(s, {kScalarRz, kScalarMaxR});
    report.converged = report.finite && report.residual <= target;
  }
  report.relativeResidual = report.initialDivergence > 0 ? report.residual / report.initialDivergence : 0;
  Stream finish(context_);
  correctVelocity(finish, levels_[0].masks, solution_[parity], velocity, velocityOut);
  if (parity == 1) finish.copy(solution_[1], solution_[0]);
  finish.submit();
  return report;
}

}  // namespace smokesvd::physics
