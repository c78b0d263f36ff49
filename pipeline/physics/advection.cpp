#include "pipeline/physics/advection.h"

#include <array>
#include <string>

#include "runtime/error.h"

namespace smokesvd::physics {
namespace {

// One invocation per cell on a 3D grid; 16 cells along x fill two 8-lane SIMD rows on lavapipe.
constexpr std::array<uint32_t, 3> kWorkgroup{16, 4, 1};

// The push block of every advection kernel (AdvectPush in shaders/physics/advect_sampling.glsl).
struct AdvectPush {
  int32_t nx, ny, nz;
  int32_t plane;
  float dt;
  float strength;
  float directScale;
  int32_t hasPrior;
};

// What is advected: one scalar plane at cell centres, or the three component planes of a MAC field.
struct Planes {
  GridSize grid;
  int count = 1;
  bool mac = false;

  AdvectPush push(int plane, float dt, float strength = 1.0f) const {
    return {static_cast<int32_t>(grid.x),
            static_cast<int32_t>(grid.y),
            static_cast<int32_t>(grid.z),
            plane,
            dt,
            strength,
            0.0f,
            0};
  }
  // The specialization constant MODE of a plane: 0 scalar at cell centres, 1 + m MAC component m.
  int32_t mode(int plane) const { return mac ? plane + 1 : 0; }
  Shape vec4Shape() const { return {count, grid.z, grid.y, grid.x, 4}; }
  std::array<uint32_t, 3> groups() const {
    return {static_cast<uint32_t>((grid.x + kWorkgroup[0] - 1) / kWorkgroup[0]),
            static_cast<uint32_t>((grid.y + kWorkgroup[1] - 1) / kWorkgroup[1]), static_cast<uint32_t>(grid.z)};
  }
};

Planes planesOf(const FlagGrid& flags, const Tensor& field, const Tensor& velocity, const char* op) {
  const std::string prefix(op);
  Planes planes;
  planes.grid = flags.size();
  requireVector(velocity, planes.grid, (prefix + ": velocity").c_str());
  const bool scalar = field.rank() == 3 || (field.rank() == 4 && field.size(0) == 1);
  if (scalar) {
    requireVolume(field, planes.grid, (prefix + ": field").c_str());
  } else {
    requireVector(field, planes.grid, (prefix + ": MAC field").c_str());
    planes.count = 3;
    planes.mac = true;
  }
  return planes;
}

void requireLike(const Tensor& tensor, const Tensor& like, const std::string& what) {
  if (tensor.numel() != like.numel())
    throw Error(what + ": expected " + toString(like.shape()) + ", got " + toString(tensor.shape()));
}

void semiLagrangianPass(Stream& stream, const Planes& planes, const Tensor& field, const Tensor& velocity,
                        const Tensor* inflow, float dt, const Tensor& out) {
  for (int plane = 0; plane < planes.count; ++plane) {
    const Kernel& kernel = stream.kernel("physics/advect_sl", kWorkgroup, {planes.mode(plane), inflow ? 1 : 0});
    stream.dispatch(kernel, {field, velocity, inflow ? *inflow : field, out}, planes.push(plane, dt), planes.groups());
  }
}

AdvectionCache macCormackPrepare(Stream& stream, const Planes& planes, const FlagGrid& flags, const Tensor& field,
                                 const Tensor& velocity, const AdvectionParams& params) {
  Context& context = stream.context();
  AdvectionCache cache{Tensor(context, field.shape()), Tensor(context, planes.vec4Shape()),
                       Tensor(context, planes.vec4Shape())};
  for (int plane = 0; plane < planes.count; ++plane) {
    const Kernel& kernel = stream.kernel("physics/advect_mc_prepare", kWorkgroup, {planes.mode(plane)});
    stream.dispatch(kernel, {flags.masks(), field, velocity, cache.firstOrder, cache.trace, cache.bounds},
                    planes.push(plane, params.dt, params.strength), planes.groups());
  }
  return cache;
}

// The gather adjoints' view of one trace direction: per cell and plane the departure stencil (vec4),
// and per tile of kTile³ cells the window of targets a source cell gathers from
// (shaders/physics/advect_tiles.glsl).
constexpr int64_t kTile = 8;

struct Trace {
  Tensor departure;
  Tensor window;
};

Trace trace(Stream& stream, const Planes& planes, const Tensor& velocity, float dt) {
  Context& context = stream.context();
  const GridSize& g = planes.grid;
  const std::array<uint32_t, 3> tiles{static_cast<uint32_t>((g.x + kTile - 1) / kTile),
                                      static_cast<uint32_t>((g.y + kTile - 1) / kTile),
                                      static_cast<uint32_t>((g.z + kTile - 1) / kTile)};
  const int64_t tileCount = int64_t{tiles[0]} * tiles[1] * tiles[2];
  Trace result{Tensor(context, planes.vec4Shape()), Tensor(context, {planes.count, tileCount, 8})};
  const Tensor reach(context, {planes.count, tileCount + 1, 8});
  const std::array<uint32_t, 3> tileGroups{(tiles[0] + 7) / 8, tiles[1], tiles[2]};
  for (int plane = 0; plane < planes.count; ++plane) {
    const AdvectPush push = planes.push(plane, dt);
    stream.dispatch(stream.kernel("physics/advect_trace", kWorkgroup, {planes.mode(plane)}),
                    {velocity, result.departure}, push, planes.groups());
    stream.dispatch(stream.kernel("physics/advect_tile_reach", {8, 1, 1}), {asVec4(result.departure), reach}, push,
                    tileGroups);
    stream.dispatch(stream.kernel("physics/advect_reach", {64, 1, 1}), {reach}, push, {1, 1, 1});
    stream.dispatch(stream.kernel("physics/advect_window", {8, 1, 1}), {reach, result.window}, push, tileGroups);
  }
  return result;
}

// One semi-Lagrangian adjoint: gradField = directScale·direct + Sᵀ upstream, traceGrad = prior + ∂/∂v.
void semiLagrangianAdjoint(Stream& stream, const Planes& planes, const Trace& traced, float dt, const Tensor& upstream,
                           const Tensor& field, const Tensor* direct, float directScale, const Tensor* prior,
                           const Tensor& gradField, const Tensor& traceGrad) {
  for (int plane = 0; plane < planes.count; ++plane) {
    const Kernel& kernel = stream.kernel("physics/advect_sl_adjoint", kWorkgroup, {planes.mode(plane)});
    AdvectPush push = planes.push(plane, dt);
    push.directScale = direct ? directScale : 0.0f;
    push.hasPrior = prior ? 1 : 0;
    stream.dispatch(kernel,
                    {upstream, field, asVec4(traced.departure), traced.window, direct ? *direct : upstream,
                     prior ? *prior : upstream, gradField, traceGrad},
                    push, planes.groups());
  }
}

}  // namespace

void advect(Stream& stream, const FlagGrid& flags, const Tensor& field, const Tensor& velocity, const Tensor* inflow,
            const AdvectionParams& params, const Tensor& out, AdvectionCache* cache) {
  const Planes planes = planesOf(flags, field, velocity, "advect");
  requireLike(out, field, "advect: output");
  if (inflow) requireLike(*inflow, field, "advect: inflow");
  if (params.scheme == AdvectionScheme::SemiLagrangian) {
    semiLagrangianPass(stream, planes, field, velocity, inflow, params.dt, out);
    if (cache) *cache = {};
    return;
  }
  if (!cache) {
    // No adjoint will follow: first-order values only, the correction recomputes what it needs.
    const Tensor firstOrder(stream.context(), field.shape());
    semiLagrangianPass(stream, planes, field, velocity, nullptr, params.dt, firstOrder);
    for (int plane = 0; plane < planes.count; ++plane) {
      const Kernel& kernel = stream.kernel("physics/advect_mc_fused", kWorkgroup, {planes.mode(plane), inflow ? 1 : 0});
      stream.dispatch(kernel, {flags.masks(), field, velocity, firstOrder, inflow ? *inflow : field, out},
                      planes.push(plane, params.dt, params.strength), planes.groups());
    }
    return;
  }
  const AdvectionCache prepared = macCormackPrepare(stream, planes, flags, field, velocity, params);
  for (int plane = 0; plane < planes.count; ++plane) {
    const Kernel& kernel = stream.kernel("physics/advect_mc", kWorkgroup, {planes.mode(plane), inflow ? 1 : 0});
    stream.dispatch(
        kernel, {prepared.firstOrder, asVec4(prepared.trace), asVec4(prepared.bounds), inflow ? *inflow : field, out},
        planes.push(plane, params.dt, params.strength), planes.groups());
  }
  *cache = prepared;
}

void advectBackward(Stream& stream, const FlagGrid& flags, const Tensor& field, const Tensor& velocity,
                    const AdvectionParams& params, const Tensor& gradOut, const AdvectionCache* cache,
                    const AdvectionGradients& gradients) {
  const Planes planes = planesOf(flags, field, velocity, "advect backward");
  requireLike(gradOut, field, "advect backward: upstream gradient");
  if (gradients.field) requireLike(*gradients.field, field, "advect backward: field gradient");
  if (gradients.velocity) requireVector(*gradients.velocity, planes.grid, "advect backward: velocity gradient");
  if (!gradients.field && !gradients.velocity) return;

  Context& context = stream.context();
  const Tensor gradField = gradients.field ? *gradients.field : Tensor(context, field.shape());
  const Tensor traceGrad(context, {planes.count, 3, planes.grid.z, planes.grid.y, planes.grid.x});
  const Trace forwardTrace = trace(stream, planes, velocity, params.dt);

  if (params.scheme == AdvectionScheme::SemiLagrangian) {
    semiLagrangianAdjoint(stream, planes, forwardTrace, params.dt, gradOut, field, nullptr, 0.0f, nullptr, gradField,
                          traceGrad);
  } else {
    const bool cached = cache && cache->firstOrder.defined();
    if (cached && (cache->firstOrder.numel() != field.numel() || cache->trace.shape() != planes.vec4Shape() ||
                   cache->bounds.shape() != planes.vec4Shape()))
      throw Error("advect backward: the cache does not belong to a field " + toString(field.shape()));
    const AdvectionCache prepared = cached ? *cache : macCormackPrepare(stream, planes, flags, field, velocity, params);
    const Tensor& forward = prepared.firstOrder;
    const Trace backwardTrace = trace(stream, planes, velocity, -params.dt);

    const Tensor gradBwd(context, field.shape());
    for (int plane = 0; plane < planes.count; ++plane) {
      const Kernel& mask = stream.kernel("physics/advect_mc_adjoint", kWorkgroup, {planes.mode(plane)});
      stream.dispatch(mask, {forward, asVec4(prepared.trace), asVec4(prepared.bounds), gradOut, gradBwd},
                      planes.push(plane, params.dt, params.strength), planes.groups());
    }

    // ∂L/∂fwd = g + S_−vᵀ gradBwd, then ∂L/∂field = S_vᵀ ∂L/∂fwd − gradBwd.
    const Tensor gradForward(context, field.shape());
    const Tensor backwardTraceGrad(context, traceGrad.shape());
    semiLagrangianAdjoint(stream, planes, backwardTrace, -params.dt, gradBwd, forward, &gradOut, 1.0f, nullptr,
                          gradForward, backwardTraceGrad);
    semiLagrangianAdjoint(stream, planes, forwardTrace, params.dt, gradForward, field, &gradBwd, -1.0f,
                          &backwardTraceGrad, gradField, traceGrad);
  }

  if (gradients.velocity) {
    const Kernel& kernel = stream.kernel("physics/advect_velocity_adjoint", kWorkgroup, {0, planes.mac ? 1 : 0});
    stream.dispatch(kernel, {traceGrad, *gradients.velocity}, planes.push(0, params.dt), planes.groups());
  }
}

}  // namespace smokesvd::physics
