#include "pipeline/physics/advection.h"

#include <array>
#include <string>

#include "pipeline/physics/grid.h"
#include "runtime/error.h"

namespace smokesvd::physics {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{64, 1, 1};

// The push block of every advection kernel (AdvectPush in shaders/physics/advect_sampling.glsl).
struct AdvectPush {
  int32_t nx, ny, nz;
  int32_t mode;
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
    return {static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z),
            mac ? plane + 1 : 0, plane, dt, strength, 0.0f, 0};
  }
  uint64_t cells() const { return static_cast<uint64_t>(grid.cells()); }
};

Planes planesOf(const Tensor& flags, const Tensor& field, const Tensor& velocity, const char* op) {
  const std::string prefix(op);
  Planes planes;
  planes.grid = volumeGrid(flags, (prefix + ": flags").c_str());
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
  const Kernel& kernel = stream.kernel("physics/advect_sl", kWorkgroup, {inflow ? 1 : 0});
  for (int plane = 0; plane < planes.count; ++plane)
    stream.dispatchFlat(kernel, {field, velocity, inflow ? *inflow : field, out}, planes.push(plane, dt),
                        planes.cells());
}

// Departure points (vec4 per cell and plane) and the reach of each plane, for the gather adjoints.
struct Trace {
  Tensor departure;
  Tensor reach;
};

Trace trace(Stream& stream, const Planes& planes, const Tensor& velocity, float dt) {
  Context& context = stream.context();
  Trace result{Tensor(context, {planes.count, planes.grid.z, planes.grid.y, planes.grid.x, 4}),
               Tensor(context, {planes.count, 8})};
  stream.fillZero(result.reach);
  const Kernel& kernel = stream.kernel("physics/advect_trace", kWorkgroup);
  for (int plane = 0; plane < planes.count; ++plane)
    stream.dispatchFlat(kernel, {velocity, result.departure, result.reach}, planes.push(plane, dt), planes.cells());
  return result;
}

// One semi-Lagrangian adjoint: gradField = directScale·direct + Sᵀ upstream, traceGrad = prior + ∂/∂v.
void semiLagrangianAdjoint(Stream& stream, const Planes& planes, const Trace& traced, float dt, const Tensor& upstream,
                           const Tensor& field, const Tensor* direct, float directScale, const Tensor* prior,
                           const Tensor& gradField, const Tensor& traceGrad) {
  const Kernel& kernel = stream.kernel("physics/advect_sl_adjoint", kWorkgroup);
  for (int plane = 0; plane < planes.count; ++plane) {
    AdvectPush push = planes.push(plane, dt);
    push.directScale = direct ? directScale : 0.0f;
    push.hasPrior = prior ? 1 : 0;
    stream.dispatchFlat(kernel,
                        {upstream, field, asVec4(traced.departure), traced.reach, direct ? *direct : upstream,
                         prior ? *prior : upstream, gradField, traceGrad},
                        push, planes.cells());
  }
}

}  // namespace

AdvectionScheme parseAdvectionScheme(const std::string& name) {
  if (name == "sl" || name == "semi-lagrangian") return AdvectionScheme::SemiLagrangian;
  if (name == "mc" || name == "maccormack") return AdvectionScheme::MacCormack;
  throw Error("advection scheme '" + name + "': expected sl (semi-lagrangian) or mc (maccormack)");
}

void advect(Stream& stream, const Tensor& flags, const Tensor& field, const Tensor& velocity, const Tensor* inflow,
            const AdvectionParams& params, const Tensor& out, const Tensor* firstOrder) {
  const Planes planes = planesOf(flags, field, velocity, "advect");
  requireLike(out, field, "advect: output");
  if (inflow) requireLike(*inflow, field, "advect: inflow");
  if (params.scheme == AdvectionScheme::SemiLagrangian) {
    semiLagrangianPass(stream, planes, field, velocity, inflow, params.dt, out);
    return;
  }
  if (firstOrder) requireLike(*firstOrder, field, "advect: first-order pass");
  const Tensor forward = firstOrder ? *firstOrder : Tensor(stream.context(), field.shape());
  semiLagrangianPass(stream, planes, field, velocity, nullptr, params.dt, forward);
  const Kernel& kernel = stream.kernel("physics/advect_mc", kWorkgroup, {inflow ? 1 : 0});
  for (int plane = 0; plane < planes.count; ++plane)
    stream.dispatchFlat(kernel, {flags, field, forward, velocity, inflow ? *inflow : field, out},
                        planes.push(plane, params.dt, params.strength), planes.cells());
}

void advectBackward(Stream& stream, const Tensor& flags, const Tensor& field, const Tensor& velocity,
                    const AdvectionParams& params, const Tensor& gradOut, const Tensor* firstOrder,
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
    if (firstOrder) requireLike(*firstOrder, field, "advect backward: first-order pass");
    Tensor forward = firstOrder ? *firstOrder : Tensor(context, field.shape());
    if (!firstOrder) semiLagrangianPass(stream, planes, field, velocity, nullptr, params.dt, forward);
    const Trace backwardTrace = trace(stream, planes, velocity, -params.dt);

    const Tensor gradBwd(context, field.shape());
    const Kernel& mask = stream.kernel("physics/advect_mc_adjoint", kWorkgroup);
    for (int plane = 0; plane < planes.count; ++plane)
      stream.dispatchFlat(mask, {flags, field, forward, velocity, gradOut, gradBwd},
                          planes.push(plane, params.dt, params.strength), planes.cells());

    // ∂L/∂fwd = g + S_−vᵀ gradBwd, then ∂L/∂field = S_vᵀ ∂L/∂fwd − gradBwd.
    const Tensor gradForward(context, field.shape());
    const Tensor backwardTraceGrad(context, traceGrad.shape());
    semiLagrangianAdjoint(stream, planes, backwardTrace, -params.dt, gradBwd, forward, &gradOut, 1.0f, nullptr,
                          gradForward, backwardTraceGrad);
    semiLagrangianAdjoint(stream, planes, forwardTrace, params.dt, gradForward, field, &gradBwd, -1.0f,
                          &backwardTraceGrad, gradField, traceGrad);
  }

  if (gradients.velocity) {
    const Kernel& kernel = stream.kernel("physics/advect_velocity_adjoint", kWorkgroup, {planes.mac ? 1 : 0});
    stream.dispatchFlat(kernel, {traceGrad, *gradients.velocity}, planes.push(0, params.dt), planes.cells());
  }
}

}  // namespace smokesvd::physics
