#include "pipeline/differentiable/physics.h"

#include <string>

#include "nets/op_registry.h"
#include "pipeline/differentiable/example_draws.h"
#include "runtime/error.h"

namespace smokesvd::diff {
namespace {

Tensor like(const Tape& tape, const Var& v) { return Tensor(tape.context(), v->value.shape()); }

// An op y = L(x) whose adjoint is a kernel of the same form: out = forward(x), grad_x = adjoint(grad_y).
template <typename Forward, typename Adjoint>
Var linearOp(Tape& tape, const Var& x, Shape outShape, Forward forward, Adjoint adjoint) {
  Tensor y(tape.context(), std::move(outShape));
  forward(tape.stream(), x->value, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, adjoint](Tape& t) {
      Tensor gx = like(t, x);
      adjoint(t.stream(), t.grad(out), gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

Shape volumeOf(const Var& velocity, const char* what) {
  return physics::vectorGrid(velocity->value, what).volume();
}

}  // namespace

Var advect(Tape& tape, const physics::FlagGrid& grid, const Var& field, const Var& velocity, const Var& inflow,
           const physics::AdvectionParams& params) {
  Tensor y = like(tape, field);
  const bool needsGrad = tape.gradEnabled() && (field->requiresGrad || velocity->requiresGrad);
  auto cache = std::make_shared<physics::AdvectionCache>();
  physics::advect(tape.stream(), grid, field->value, velocity->value, inflow ? &inflow->value : nullptr, params, y,
                  needsGrad ? cache.get() : nullptr);
  Var out = inflow ? tape.output(y, {field, velocity, inflow}) : tape.output(y, {field, velocity});
  if (out->requiresGrad) {
    tape.record({out}, [grid, field, velocity, inflow, out, params, cache](Tape& t) {
      const Tensor g = t.grad(out);
      Tensor gradField = field->requiresGrad ? like(t, field) : Tensor();
      Tensor gradVelocity = velocity->requiresGrad ? like(t, velocity) : Tensor();
      physics::advectBackward(t.stream(), grid, field->value, velocity->value, params, g,
                              cache->firstOrder.defined() ? cache.get() : nullptr,
                              {.field = field->requiresGrad ? &gradField : nullptr,
                               .velocity = velocity->requiresGrad ? &gradVelocity : nullptr});
      if (field->requiresGrad) t.accumulate(field, gradField);
      if (velocity->requiresGrad) t.accumulate(velocity, gradVelocity);
      if (inflow) t.accumulate(inflow, g);
    });
  }
  return out;
}

Var macToCentred(Tape& tape, const Var& mac) {
  return linearOp(tape, mac, mac->value.shape(), physics::macToCentred, physics::centredToMac);
}

Var centredToMac(Tape& tape, const Var& centred) {
  return linearOp(tape, centred, centred->value.shape(), physics::centredToMac, physics::macToCentred);
}

Var divergence(Tape& tape, const Var& velocity, physics::Staggering staggering) {
  return linearOp(
      tape, velocity, volumeOf(velocity, "divergence: velocity"),
      [staggering](Stream& s, const Tensor& u, const Tensor& y) { physics::divergence(s, u, staggering, y); },
      [staggering](Stream& s, const Tensor& g, const Tensor& gu) {
        physics::divergenceBackward(s, staggering, g, gu);
      });
}

Var curl(Tape& tape, const Var& velocity) {
  return linearOp(tape, velocity, velocity->value.shape(), physics::curl, physics::curlBackward);
}

Var gradientNormSquared(Tape& tape, const Var& velocity) {
  Tensor y(tape.context(), volumeOf(velocity, "gradient norm: velocity"));
  physics::gradientNormSquared(tape.stream(), velocity->value, y);
  Var out = tape.output(y, {velocity});
  if (out->requiresGrad) {
    tape.record({out}, [velocity, out](Tape& t) {
      Tensor gu = like(t, velocity);
      physics::gradientNormSquaredBackward(t.stream(), velocity->value, t.grad(out), gu);
      t.accumulate(velocity, gu);
    });
  }
  return out;
}

Var velocityToPlanar(Tape& tape, const Var& interleaved) {
  const Shape& s = interleaved->value.shape();
  if (s.size() != 4 || s[3] != 3)
    throw Error("velocity to planar: expected [D, H, W, 3], got " + toString(s));
  return linearOp(tape, interleaved, {3, s[0], s[1], s[2]}, physics::interleavedToPlanar, physics::planarToInterleaved);
}

Var velocityToInterleaved(Tape& tape, const Var& planar) {
  const GridSize grid = physics::vectorGrid(planar->value, "velocity to interleaved");
  return linearOp(tape, planar, {grid.z, grid.y, grid.x, 3}, physics::planarToInterleaved,
                  physics::interleavedToPlanar);
}

namespace {

std::vector<Var> one(Var v) { return {std::move(v)}; }

physics::Staggering parseStaggering(const std::string& name) {
  if (name == "mac") return physics::Staggering::Mac;
  if (name == "centred") return physics::Staggering::Centred;
  throw Error("staggering '" + name + "': expected mac or centred");
}

physics::AdvectionScheme parseOrder(int64_t order) {
  if (order == 1) return physics::AdvectionScheme::SemiLagrangian;
  if (order == 2) return physics::AdvectionScheme::MacCormack;
  throw Error("advect: order=" + std::to_string(order) + ", expected 1 (semi-Lagrangian) or 2 (MacCormack)");
}

std::vector<Var> applyAdvect(Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
  const Var& field = in[0];
  const Var& velocity = in[1];
  const Var& inflow = in[2];
  const Var& flags = in[3];
  const GridSize grid = physics::vectorGrid(velocity->value, "advect: velocity");
  const physics::FlagGrid flagGrid(tape.stream(),
                                   flags ? flags->value : physics::closedBoxFlagsTensor(tape.context(), grid));
  const physics::AdvectionParams params{.scheme = parseOrder(attrs.integer("order")),
                                        .dt = static_cast<float>(attrs.number("dt")),
                                        .strength = static_cast<float>(attrs.number("strength"))};
  return one(advect(tape, flagGrid, field, velocity, inflow, params));
}

// Velocities of up to `speed` cells per step on a [D, H, W] grid.
InputDraw velocityDraw(const Shape& volume, float speed) {
  return draw::uniform({3, volume[0], volume[1], volume[2]}, -speed, speed);
}

// Advection is piecewise smooth: a trace crossing a cell face or MacCormack switching between its
// correction and the clamp is a kink, so the steps stay small.
std::vector<OpExample> advectExamples() {
  const Shape odd{5, 6, 7}, aligned{4, 5, 8};
  const GradientCheck smallStep{.step = 1e-3, .rtol = 3e-3, .atol = 1e-5};
  return {{.name = "semi-Lagrangian, density",
           .inputs = {{"field", draw::uniform(odd, 0, 1)}, {"velocity", velocityDraw(odd, 1.2f)}},
           .attrs = {{"order", "1"}},
           .gradient = smallStep},
          {.name = "MacCormack, density, inflow, obstacles and empty cells",
           .inputs = {{"field", draw::uniform(odd, 0, 1)},
                      {"velocity", velocityDraw(odd, 1.2f)},
                      {"inflow", draw::uniform(odd, 0, 0.5f)},
                      {"flags", flagsDraw(odd)}},
           .attrs = {{"dt", "0.8"}},
           .gradient = smallStep},
          {.name = "MacCormack, MAC velocity field, 4-aligned width",
           .inputs = {{"field", velocityDraw(aligned, 1)}, {"velocity", velocityDraw(aligned, 1)}},
           .attrs = {{"strength", "0.7"}},
           .gradient = smallStep},
          {.name = "semi-Lagrangian, MAC field, inflow",
           .inputs = {{"field", velocityDraw(odd, 1)}, {"velocity", velocityDraw(odd, 1)}, {"inflow", velocityDraw(odd, 0.5f)}},
           .attrs = {{"order", "1"}, {"dt", "0.5"}},
           .gradient = smallStep}};
}

// A linear op of one vector field [3, D, H, W] (or, interleaved, [D, H, W, 3]): odd and 4-aligned grids.
std::vector<OpExample> vectorFieldExamples(std::map<std::string, std::string> attrs = {}, const std::string& input = "x",
                                           bool interleaved = false) {
  auto field = [interleaved](Shape grid) {
    return draw::uniform(interleaved ? Shape{grid[0], grid[1], grid[2], 3} : Shape{3, grid[0], grid[1], grid[2]});
  };
  return {{.name = "odd grid", .inputs = {{input, field({5, 6, 7})}}, .attrs = attrs, .gradient = {.step = 0.25}},
          {.name = "4-aligned width", .inputs = {{input, field({3, 4, 8})}}, .attrs = attrs, .gradient = {.step = 0.25}}};
}

const bool registered =
    registerOp({"advect",
                "out = A(field, velocity) + inflow: field [D,H,W] at cell centres or MAC [3,D,H,W], velocity MAC "
                "[3,D,H,W] in cells per step, flags (mantaflow bits) default to a closed box",
                {"field", "velocity"},
                {"inflow", "flags"},
                {{"order", "2", "1 semi-Lagrangian, 2 MacCormack (revert-to-first-order clamp)"},
                 {"dt", "1", "time step"},
                 {"strength", "1", "MacCormack correction strength"}},
                {"out"},
                applyAdvect,
                advectExamples()}) &&
    registerOp({"mac_to_centred", "y = cell-centred average of a MAC velocity [3,D,H,W]", {"x"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(macToCentred(t, in[0])); },
                vectorFieldExamples()}) &&
    registerOp({"centred_to_mac", "y = MAC face average of a cell-centred velocity [3,D,H,W]", {"x"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(centredToMac(t, in[0])); },
                vectorFieldExamples()}) &&
    registerOp({"divergence", "y [D,H,W] = divergence of a velocity [3,D,H,W]", {"velocity"}, {},
                {{"staggering", "mac", "mac (face differences) or centred (central differences)"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return one(divergence(t, in[0], parseStaggering(attrs.text("staggering"))));
                },
                {vectorFieldExamples({{"staggering", "mac"}}, "velocity")[0],
                 {.name = "centred, 4-aligned width",
                  .inputs = {{"velocity", draw::uniform({3, 3, 4, 8})}},
                  .attrs = {{"staggering", "centred"}},
                  .gradient = {.step = 0.25}}}}) &&
    registerOp({"curl", "y [3,D,H,W] = curl of a cell-centred velocity [3,D,H,W]", {"velocity"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(curl(t, in[0])); },
                vectorFieldExamples({}, "velocity")}) &&
    registerOp({"gradient_norm", "y [D,H,W] = squared Frobenius norm of the velocity gradient (cell-centred)",
                {"velocity"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) {
                  return one(gradientNormSquared(t, in[0]));
                },
                {{.name = "odd grid", .inputs = {{"velocity", draw::uniform({3, 5, 6, 7})}}},
                 {.name = "4-aligned width", .inputs = {{"velocity", draw::uniform({3, 3, 4, 8})}}}}}) &&
    registerOp({"velocity_to_planar", "y [3,D,H,W] = x [D,H,W,3] (file layout to kernel layout)", {"x"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(velocityToPlanar(t, in[0])); },
                vectorFieldExamples({}, "x", true)}) &&
    registerOp({"velocity_to_interleaved", "y [D,H,W,3] = x [3,D,H,W] (kernel layout to file layout)", {"x"}, {}, {},
                {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) {
                  return one(velocityToInterleaved(t, in[0]));
                },
                vectorFieldExamples()});

}  // namespace
}  // namespace smokesvd::diff
