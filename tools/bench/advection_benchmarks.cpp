// Advection benchmarks: semi-Lagrangian and MacCormack, forward and adjoint (w.r.t. field and
// velocity), for a 64³ scalar field and for the paper's 64x112x64 density plus MAC velocity
// self-advection, next to one trilinear resample of the 64³ volume for scale. The flow is a smooth swirl
// rising at up to ~1.5 cells per step.
// Bytes count each tensor a dispatch reads or writes once (float32): SL reads field + 3 velocity
// planes and writes 1 plane; the MacCormack pass reads flags, field, first-order pass and velocity.
#include <cmath>
#include <string>

#include "pipeline/physics/advection.h"
#include "pipeline/physics/grid.h"
#include "pipeline/render/rotate.h"
#include "tools/bench/bench.h"

namespace smokesvd::bench {
namespace {

using physics::AdvectionScheme;

struct Scene {
  GridSize grid;
  physics::FlagGrid flags;
  Tensor density, velocity;
};

Scene makeScene(Context& context, const GridSize& grid) {
  const int64_t cells = grid.cells();
  std::vector<float> density(static_cast<std::size_t>(cells));
  std::vector<float> velocity(static_cast<std::size_t>(3 * cells));
  const double cx = static_cast<double>(grid.x) / 2, cy = static_cast<double>(grid.y) / 3,
               cz = static_cast<double>(grid.z) / 2;
  std::size_t at = 0;
  for (int64_t k = 0; k < grid.z; ++k)
    for (int64_t j = 0; j < grid.y; ++j)
      for (int64_t i = 0; i < grid.x; ++i, ++at) {
        const double x = static_cast<double>(i) + 0.5 - cx, y = static_cast<double>(j) + 0.5 - cy,
                     z = static_cast<double>(k) + 0.5 - cz;
        const double r2 = (x * x + y * y + z * z) / (0.04 * static_cast<double>(grid.x * grid.x));
        density[at] = static_cast<float>(std::exp(-r2));
        velocity[at] = static_cast<float>(-0.04 * z);
        velocity[static_cast<std::size_t>(cells) + at] =
            static_cast<float>(0.3 + 1.2 * std::exp(-(x * x + z * z) / 200.0));
        velocity[static_cast<std::size_t>(2 * cells) + at] = static_cast<float>(0.04 * x);
      }
  Stream stream(context);
  Scene scene{grid, physics::FlagGrid(stream, physics::closedBoxFlagsTensor(context, grid)),
              Tensor::fromHost(context, grid.volume(), density), Tensor::fromHost(context, grid.vector(), velocity)};
  stream.submit();
  return scene;
}

std::string shapeOf(const GridSize& grid, const char* what) {
  return std::to_string(grid.x) + "x" + std::to_string(grid.y) + "x" + std::to_string(grid.z) + " " + what;
}

// Nominal bytes of one forward step of `planes` planes.
double forwardBytes(const GridSize& grid, int planes, AdvectionScheme scheme) {
  const double plane = 4.0 * static_cast<double>(grid.cells());
  const double semiLagrangian = planes * (1 + 3 + 1) * plane;
  const double correction = planes * (1 + 1 + 1 + 3 + 1) * plane;
  return scheme == AdvectionScheme::SemiLagrangian ? semiLagrangian : semiLagrangian + correction;
}

// Nominal bytes of the adjoint: trace (velocity in, departure vec4 out), SL adjoint (upstream,
// departures, field, direct, prior, out, 3 trace-gradient planes in and out), the MacCormack mask,
// and the velocity adjoint (3·planes trace-gradient planes in, 3 out).
double adjointBytes(const GridSize& grid, int planes, AdvectionScheme scheme) {
  const double plane = 4.0 * static_cast<double>(grid.cells());
  const double traceBytes = planes * (3 + 4) * plane;
  const double slAdjoint = planes * (1 + 4 + 1 + 1 + 3 + 1 + 3) * plane;
  const double mask = planes * (1 + 1 + 1 + 3 + 1 + 1) * plane;
  const double velocityAdjoint = (3.0 * planes + 3) * plane;
  if (scheme == AdvectionScheme::SemiLagrangian) return traceBytes + slAdjoint + velocityAdjoint;
  return 2 * traceBytes + mask + 2 * slAdjoint + velocityAdjoint;
}

const char* schemeName(AdvectionScheme scheme) { return scheme == AdvectionScheme::SemiLagrangian ? "sl" : "mc"; }

void scalar64(BenchContext& b) {
  const Scene scene = makeScene(b.context(), {.x = 64, .y = 64, .z = 64});
  Tensor out(b.context(), scene.grid.volume());
  physics::AdvectionCache cache;
  Tensor gradOut(b.context(), scene.grid.volume());
  Tensor gradDensity(b.context(), scene.grid.volume());
  Tensor gradVelocity(b.context(), scene.grid.vector());
  Stream fill(b.context());
  fill.copy(scene.density, gradOut);
  fill.submit();
  // The yardstick of the MacCormack target: one trilinear resample of the same volume through texel
  // buffers (a rotation about the vertical axis); MacCormack should cost about three of these.
  b.measure("advect/resample-reference", shapeOf(scene.grid, "rotated 30 deg"), 2.0 * 4.0 * static_cast<double>(scene.grid.cells()), 0,
            [&](Stream& s) { render::rotate(s, scene.density, 30.0, out); });
  for (AdvectionScheme scheme : {AdvectionScheme::SemiLagrangian, AdvectionScheme::MacCormack}) {
    const physics::AdvectionParams params{.scheme = scheme};
    const std::string name = std::string("advect/") + schemeName(scheme) + "-scalar";
    b.measure(name, shapeOf(scene.grid, "density"), forwardBytes(scene.grid, 1, scheme), 0, [&](Stream& s) {
      physics::advect(s, scene.flags, scene.density, scene.velocity, nullptr, params, out, &cache);
    });
    b.measure(name + "-no-cache", shapeOf(scene.grid, "density"), forwardBytes(scene.grid, 1, scheme), 0,
              [&](Stream& s) { physics::advect(s, scene.flags, scene.density, scene.velocity, nullptr, params, out); });
    b.measure(name + "-adjoint", shapeOf(scene.grid, "density"), adjointBytes(scene.grid, 1, scheme), 0,
              [&](Stream& s) {
                physics::advectBackward(s, scene.flags, scene.density, scene.velocity, params, gradOut, &cache,
                                        {.field = &gradDensity, .velocity = &gradVelocity});
              });
  }
}

void paperStep(BenchContext& b) {
  const Scene scene = makeScene(b.context(), {.x = 64, .y = 112, .z = 64});
  const GridSize& grid = scene.grid;
  Tensor density(b.context(), grid.volume()), velocity(b.context(), grid.vector());
  physics::AdvectionCache densityCache, velocityCache;
  Tensor gradDensity(b.context(), grid.volume()), gradVelocity(b.context(), grid.vector());
  Tensor gradFromDensity(b.context(), grid.vector()), gradFromField(b.context(), grid.vector());
  Tensor gradFromVelocity(b.context(), grid.vector());
  for (AdvectionScheme scheme : {AdvectionScheme::SemiLagrangian, AdvectionScheme::MacCormack}) {
    const physics::AdvectionParams params{.scheme = scheme};
    const std::string name = std::string("advect/") + schemeName(scheme) + "-density+velocity";
    const double forward = forwardBytes(grid, 1, scheme) + forwardBytes(grid, 3, scheme);
    b.measure(name, shapeOf(grid, "density + MAC"), forward, 0, [&](Stream& s) {
      physics::advect(s, scene.flags, scene.density, scene.velocity, nullptr, params, density, &densityCache);
      physics::advect(s, scene.flags, scene.velocity, scene.velocity, nullptr, params, velocity, &velocityCache);
    });
    const double adjoint = adjointBytes(grid, 1, scheme) + adjointBytes(grid, 3, scheme);
    b.measure(name + "-adjoint", shapeOf(grid, "density + MAC"), adjoint, 0, [&](Stream& s) {
      physics::advectBackward(s, scene.flags, scene.density, scene.velocity, params, scene.density, &densityCache,
                              {.field = &gradDensity, .velocity = &gradFromDensity});
      physics::advectBackward(s, scene.flags, scene.velocity, scene.velocity, params, scene.velocity, &velocityCache,
                              {.field = &gradFromField, .velocity = &gradFromVelocity});
    });
  }
}

const bool registered =
    registerBenchmark({"advect/scalar-64", scalar64}) && registerBenchmark({"advect/paper-step", paperStep});

}  // namespace
}  // namespace smokesvd::bench
