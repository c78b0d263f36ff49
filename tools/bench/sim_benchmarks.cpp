// Simulation benchmarks at the paper's resolution, 64×112×64: the pressure projection alone (MGPCG to a
// relative residual of 1e-3 and 1e-4, from zero) and one full simulator step (inflow, MacCormack
// advection of density and velocity, buoyancy and wind, vorticity confinement, projection to 1e-4 with
// warm start), plus the single kernels of the projection and the forces. `sim/step-mantaflow-setup` is
// a step in the setting of the mantaflow figure it is compared with (64×96×64, no wind or vorticity,
// projection to 1e-3).
//
// The projection and the step wait for the device after every conjugate-gradient iteration, so they are
// timed on the wall clock (median of kWallRuns after one warm-up); the single kernels with GPU
// timestamps. Bytes are nominal: every field a kernel reads or writes, counted once per kernel.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "nets/ops/elementwise.h"
#include "pipeline/physics/forces.h"
#include "pipeline/physics/pressure.h"
#include "pipeline/physics/sources.h"
#include "pipeline/sim/simulator.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

constexpr int kWallRuns = 5;
const GridSize kGrid{.x = 64, .y = 112, .z = 64};
const std::string kShape = "64x112x64";

// Median wall time (ns) of `run` over kWallRuns runs after one warm-up.
template <typename Run>
double wallMedian(Run&& run) {
  std::vector<double> samples;
  for (int i = 0; i <= kWallRuns; ++i) {
    const auto start = std::chrono::steady_clock::now();
    run();
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    if (i > 0) samples.push_back(ns);
  }
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

// A plume-like state: a smooth swirling velocity (about 1 cell per step) with a rising column, and a
// density blob; `divergent` adds a non-solenoidal part so that the projection has work to do.
std::vector<float> plumeVelocity(bool divergent, const GridSize& grid = kGrid) {
  const int64_t cells = grid.cells();
  std::vector<float> velocity(static_cast<std::size_t>(3 * cells));
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const double x = static_cast<double>(i) / 64.0, y = static_cast<double>(j) / 64.0, z = static_cast<double>(k) / 64.0;
        const double column = std::exp(-((x - 0.5) * (x - 0.5) + (z - 0.5) * (z - 0.5)) * 40.0);
        const double swirl[3] = {std::sin(6.0 * y + 1.0) * std::cos(5.0 * z), 1.2 * column + 0.3 * std::sin(4.0 * x) * std::sin(5.0 * z),
                                 std::cos(6.0 * x) * std::sin(3.0 * y)};
        const double source[3] = {std::sin(9.0 * x) * 0.3, std::cos(7.0 * y) * 0.3, std::sin(8.0 * z + 2.0) * 0.3};
        for (int a = 0; a < 3; ++a)
          velocity[static_cast<std::size_t>(a * cells + i + grid.x * (j + grid.y * k))] =
              static_cast<float>(swirl[a] + (divergent ? source[a] : 0.0));
      }
  return velocity;
}

// The paper's setting: 64x112x64, MacCormack, density buoyancy, wind, vorticity confinement, projection
// to 1e-4.
sim::Scene benchmarkScene() {
  sim::Scene scene;
  scene.resolution = kGrid;
  scene.frames = 1000;
  scene.densityBuoyancy = 0.05;
  scene.wind = sim::Keyframes<Vec3>::constant({0.005, 0, 0});
  scene.vorticity = 0.1;
  sim::Source source;
  source.shape.centre = {32, 8, 32};
  source.shape.size = {7, 0, 0};
  source.noise = {0.5, 3.0, {0, 0.5, 0}, 1};
  scene.sources.push_back(source);
  return scene;
}

// The setting of the mantaflow figure the step is compared with (0.15-0.27 s per frame natively on two
// cores): a 64x96x64 plume, advection, buoyancy and a pressure solve to 1e-3, nothing else.
sim::Scene mantaflowComparisonScene() {
  sim::Scene scene = benchmarkScene();
  scene.resolution = {.x = 64, .y = 96, .z = 64};
  scene.wind = sim::Keyframes<Vec3>::constant({0, 0, 0});
  scene.vorticity = 0;
  scene.pressureTolerance = 1e-3;
  return scene;
}

// Nominal bytes of one conjugate-gradient iteration, in volumes of the level: per level the V-cycle's
// sweeps (first 3, plain 4 ×3), residual 4, restriction 1.25, prolongation 3.125; then the direction (5)
// and update (6) kernels on the fine grid.
double iterationBytes(const physics::PressureSolver& solver) {
  double cells = static_cast<double>(kGrid.cells()), total = 0;
  for (int level = 0; level < solver.levels(); ++level, cells /= 8) {
    const bool coarsest = level + 1 == solver.levels();
    total += coarsest ? (3 + 4.0 * (solver.options().coarsestSweeps - 1)) * cells : (3 + 3 * 4 + 4 + 1.25 + 3.125) * cells;
  }
  return 4.0 * (total + 11 * static_cast<double>(kGrid.cells()));
}

void projection(BenchContext& b) {
  Context& context = b.context();
  Tensor flags = physics::closedBoxFlagsTensor(context, kGrid);
  {
    std::vector<float> values = flags.download();
    for (int64_t k = 1; k < kGrid.z - 1; ++k)
      for (int64_t i = 1; i < kGrid.x - 1; ++i) values[static_cast<std::size_t>(i + kGrid.x * (kGrid.y - 1 + kGrid.y * k))] = physics::kEmpty;
    flags.upload(values);
  }
  Tensor velocity = Tensor::fromHost(context, kGrid.vector(), plumeVelocity(true));
  Tensor projected(context, kGrid.vector());
  for (double tolerance : {1e-3, 1e-4}) {
    physics::PressureOptions options;
    options.tolerance = tolerance;
    options.warmStart = false;
    physics::PressureSolver solver(context, flags, options);
    physics::PressureReport report;
    Measurement m;
    m.medianNs = wallMedian([&] { report = solver.project(velocity, projected); });
    char tolerance_[16];
    std::snprintf(tolerance_, sizeof tolerance_, "%.0e", tolerance);
    m.name = std::string("sim/projection-") + tolerance_;
    m.shape = kShape + " open top, " + std::to_string(report.iterations) + " it";
    m.bytes = report.iterations * iterationBytes(solver) + 4.0 * 14 * static_cast<double>(kGrid.cells());
    m.runs = kWallRuns;
    b.add(m);
  }
}

// Median wall time of a frame of `scene` from a rising plume state (one step per frame).
void timeStep(BenchContext& b, const std::string& name, const std::string& what, const sim::Scene& scene) {
  const GridSize& grid = scene.resolution;
  sim::Simulator simulator(b.context(), scene);
  sim::SimulatorState state;
  state.velocity = plumeVelocity(false, grid);
  state.density.assign(static_cast<std::size_t>(grid.cells()), 0.0f);
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i) {
        const double dx = static_cast<double>(i) - 32.0, dy = static_cast<double>(j) - 30.0, dz = static_cast<double>(k) - 32.0;
        const double r2 = dx * dx + dy * dy + dz * dz;
        state.density[static_cast<std::size_t>(i + grid.x * (j + grid.y * k))] = static_cast<float>(std::exp(-r2 / 100.0));
      }
  state.pressure.assign(static_cast<std::size_t>(grid.cells()), 0.0f);
  simulator.restore(state);
  int iterations = 0;
  Measurement m;
  m.medianNs = wallMedian([&] { iterations += simulator.advanceFrame().pressureIterations; });
  m.name = name;
  m.shape = std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" + std::to_string(grid.z) + " " + what + ", ~" +
            std::to_string(iterations / (kWallRuns + 1)) + " CG it";
  m.runs = kWallRuns;
  b.add(m);
}

void step(BenchContext& b) {
  timeStep(b, "sim/step", "MacCormack, 1e-4", benchmarkScene());
  timeStep(b, "sim/step-mantaflow-setup", "MacCormack, 1e-3", mantaflowComparisonScene());
}

void kernels(BenchContext& b) {
  Context& context = b.context();
  namespace pressure = physics::pressure_ops;
  const double n = static_cast<double>(kGrid.cells()) * 4.0;  // bytes of one volume (64 wide: no padding)
  Tensor flags = physics::closedBoxFlagsTensor(context, kGrid);
  Tensor masks(context, kGrid.volume()), x(context, kGrid.volume()), y(context, kGrid.volume()),
      z(context, kGrid.volume()), w(context, kGrid.volume()), v(context, kGrid.volume()), t(context, kGrid.volume());
  Tensor velocity = Tensor::fromHost(context, kGrid.vector(), plumeVelocity(true)), out(context, kGrid.vector());
  Tensor partials(context, {3 * pressure::startPartialCount(context, kGrid)}), scalars(context, {pressure::kScalarSlots});
  const GridSize coarse = pressure::coarserGrid(kGrid);
  Tensor coarseFlags(context, coarse.volume()), coarseMasks(context, coarse.volume()), coarseValues(context, coarse.volume());
  {
    Stream setup(context);
    pressure::stencilMasks(setup, flags, masks);
    pressure::coarsenFlags(setup, flags, coarseFlags);
    pressure::stencilMasks(setup, coarseFlags, coarseMasks);
    ops::fill(setup, x, 0.5f);
    ops::fill(setup, y, 0.25f);
    ops::fill(setup, coarseValues, 0.1f);
    ops::fill(setup, scalars, 0.5f);
    setup.submit();
  }
  // For scale: copying the velocity (three volumes) with the runtime's elementwise copy.
  b.measure("sim/copy-velocity", kShape, 6 * n, 0, [&](Stream& s) { ops::copy(s, velocity, out); });
  b.measure("sim/pressure-residual", kShape, 6 * n, 0, [&](Stream& s) { pressure::residual(s, masks, velocity, x, z, partials); });
  b.measure("sim/pressure-apply", kShape, 5 * n, 0,
            [&](Stream& s) { pressure::applyDirection(s, masks, x, y, scalars, z, w, partials); });
  b.measure("sim/pressure-update", kShape, 6 * n, 0,
            [&](Stream& s) { pressure::update(s, x, y, z, w, scalars, v, t, partials); });
  b.measure("sim/multigrid-smooth", kShape, 4 * n, 0,
            [&](Stream& s) { pressure::smooth(s, false, true, masks, x, y, 0.8f, z, partials); });
  b.measure("sim/multigrid-residual", kShape, 4 * n, 0, [&](Stream& s) { pressure::levelResidual(s, masks, x, y, z); });
  b.measure("sim/multigrid-restrict", kShape, 1.25 * n, 0,
            [&](Stream& s) { pressure::restrictResidual(s, x, coarseMasks, 0.5f, coarseValues); });
  b.measure("sim/multigrid-prolong", kShape, 3.125 * n, 0,
            [&](Stream& s) { pressure::prolong(s, masks, x, coarseValues, z); });
  b.measure("sim/pressure-correct", kShape, 8 * n, 0,
            [&](Stream& s) { pressure::correctVelocity(s, masks, x, velocity, out); });
  b.measure("sim/buoyancy", kShape, 8 * n, 0, [&](Stream& s) {
    physics::addBuoyancy(s, flags, x, nullptr, velocity, physics::Buoyancy{{0, 0, 0}, {0, 0.01f, 0}, {0, 0, 0}}, 1.0f, out);
  });
  Tensor vorticity(context, {4, kGrid.z, kGrid.y, kGrid.x});
  b.measure("sim/vorticity-field", kShape, 7 * n, 0, [&](Stream& s) { physics::vorticityField(s, velocity, vorticity); });
  b.measure("sim/vorticity-force", kShape, 11 * n, 0, [&](Stream& s) {
    physics::addVorticityConfinement(s, flags, vorticity, velocity, 0.1f, 1.0f, out);
  });
  physics::SourceTable sources(context, 1);
  physics::SourceState source;
  source.centre = {32, 8, 32};
  source.size = {7, 0, 0};
  source.noiseAmplitude = 0.5f;
  source.setsVelocity = true;
  source.velocity = {0, 0.5f, 0};
  sources.write({&source, 1});
  b.measure("sim/inflow-density", kShape, 4 * n, 0,
            [&](Stream& s) { physics::inflowFields(s, flags, x, nullptr, sources, 1.0f, z, nullptr); });
  b.measure("sim/inflow-velocity", kShape, 7 * n, 0,
            [&](Stream& s) { physics::applySourceVelocity(s, flags, sources, out); });
}

const bool registered = registerBenchmark({"sim/projection", projection}) && registerBenchmark({"sim/step", step}) &&
                        registerBenchmark({"sim/kernels", kernels});

}  // namespace
}  // namespace smokesvd::bench
