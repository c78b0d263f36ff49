// The simulator's forces as `smokesvd op` ops, so they can be checked against mantaflow: buoyancy with
// uniform acceleration, a cell-centred force field and vorticity confinement (pipeline/physics/forces.h,
// docs/simulation.md). They are forward-only: the simulator is not differentiated through them, and an
// upstream gradient is an error rather than a silent zero.
#include <string>

#include "nets/op_registry.h"
#include "pipeline/differentiable/example_draws.h"
#include "pipeline/physics/forces.h"
#include "runtime/error.h"

namespace smokesvd::diff {
namespace {

void requireNoGradient(const Tape& tape, const std::vector<Var>& inputs, const std::string& op) {
  if (!tape.gradEnabled()) return;
  for (const Var& input : inputs)
    if (input && input->requiresGrad)
      throw Error("op " + op + " has no backward pass (the simulator's forces are not differentiated)");
}

glm::vec3 vec3Attr(const OpAttrs& attrs, const std::string& name, const std::string& op) {
  const std::vector<double> values = attrs.numbers(name);
  if (values.size() != 3) throw Error("op " + op + ": " + name + " needs three numbers x,y,z, got '" + attrs.text(name) + "'");
  return glm::vec3(values[0], values[1], values[2]);
}

Tensor flagsOr(Tape& tape, const Var& flags, const Var& velocity, const char* what) {
  return flags ? flags->value : physics::closedBoxFlagsTensor(tape.context(), physics::vectorGrid(velocity->value, what));
}

std::vector<Var> applyBuoyancy(Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
  requireNoGradient(tape, in, "buoyancy");
  const Var &velocity = in[0], &density = in[1], &temperature = in[2], &flags = in[3];
  const physics::Buoyancy buoyancy{vec3Attr(attrs, "uniform", "buoyancy"), vec3Attr(attrs, "per_density", "buoyancy"),
                                   vec3Attr(attrs, "per_temperature", "buoyancy")};
  Tensor out(tape.context(), velocity->value.shape());
  physics::addBuoyancy(tape.stream(), flagsOr(tape, flags, velocity, "buoyancy: velocity"), density->value,
                       temperature ? &temperature->value : nullptr, velocity->value, buoyancy,
                       static_cast<float>(attrs.number("dt")), out);
  return {tape.output(out, {})};
}

std::vector<Var> applyForceField(Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
  requireNoGradient(tape, in, "force_field");
  const Var &velocity = in[0], &force = in[1], &flags = in[2];
  Tensor out(tape.context(), velocity->value.shape());
  physics::addForceField(tape.stream(), flagsOr(tape, flags, velocity, "force_field: velocity"), force->value,
                         velocity->value, static_cast<float>(attrs.number("dt")), out);
  return {tape.output(out, {})};
}

std::vector<Var> applyVorticity(Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
  requireNoGradient(tape, in, "vorticity_confinement");
  const Var &velocity = in[0], &flags = in[1];
  const GridSize grid = physics::vectorGrid(velocity->value, "vorticity_confinement: velocity");
  Tensor vorticity(tape.context(), {4, grid.z, grid.y, grid.x});
  Tensor out(tape.context(), velocity->value.shape());
  physics::vorticityField(tape.stream(), velocity->value, vorticity);
  physics::addVorticityConfinement(tape.stream(), flagsOr(tape, flags, velocity, "vorticity_confinement: velocity"),
                                   vorticity, velocity->value, static_cast<float>(attrs.number("strength")),
                                   static_cast<float>(attrs.number("dt")), out);
  return {tape.output(out, {})};
}

const AttrSpec kDt{"dt", "1", "time step"};

InputDraw velocityDraw(const Shape& volume) { return draw::uniform({3, volume[0], volume[1], volume[2]}); }

// Odd grids run the per-cell kernels, grids of a 4-aligned width the block kernels.
const Shape kOdd{5, 6, 7}, kAligned{4, 5, 8};

std::vector<OpExample> buoyancyExamples() {
  return {{.name = "density only, closed box, odd grid",
           .inputs = {{"velocity", velocityDraw(kOdd)}, {"density", draw::uniform(kOdd, 0, 1)}},
           .attrs = {{"uniform", "0.1,0,-0.2"}, {"per_density", "0,0.5,0"}}},
          {.name = "density, temperature and flags, 4-aligned width",
           .inputs = {{"velocity", velocityDraw(kAligned)},
                      {"density", draw::uniform(kAligned, 0, 1)},
                      {"temperature", draw::uniform(kAligned, 0, 1)},
                      {"flags", flagsDraw(kAligned)}},
           .attrs = {{"per_density", "0,0.5,0"}, {"per_temperature", "0.1,0.3,0"}, {"dt", "0.5"}}}};
}

std::vector<OpExample> forceFieldExamples() {
  return {{.name = "closed box, odd grid", .inputs = {{"velocity", velocityDraw(kOdd)}, {"force", velocityDraw(kOdd)}}},
          {.name = "flags, 4-aligned width",
           .inputs = {{"velocity", velocityDraw(kAligned)}, {"force", velocityDraw(kAligned)}, {"flags", flagsDraw(kAligned)}},
           .attrs = {{"dt", "0.5"}}}};
}

std::vector<OpExample> vorticityExamples() {
  return {{.name = "closed box, odd grid", .inputs = {{"velocity", velocityDraw(kOdd)}}},
          {.name = "flags, 4-aligned width",
           .inputs = {{"velocity", velocityDraw(kAligned)}, {"flags", flagsDraw(kAligned)}},
           .attrs = {{"strength", "0.3"}, {"dt", "0.5"}}}};
}

const bool registered =
    registerOp({"buoyancy",
                "out = velocity + dt (uniform + per_density rho + per_temperature T) on the faces forces act on: MAC "
                "velocity [3,D,H,W], density and temperature [D,H,W] averaged over each face's two cells, flags "
                "default to a closed box (forward only)",
                {"velocity", "density"},
                {"temperature", "flags"},
                {{"uniform", "0,0,0", "uniform acceleration x,y,z (wind, gravity), cells per step^2"},
                 {"per_density", "0,0,0", "acceleration per unit density x,y,z (mantaflow: -coefficient * gravity)"},
                 {"per_temperature", "0,0,0", "acceleration per unit temperature x,y,z"},
                 kDt},
                {"out"},
                applyBuoyancy,
                buoyancyExamples(),
                Differentiable::No}) &&
    registerOp({"force_field",
                "out = velocity + dt * face average of a cell-centred acceleration force [3,D,H,W] (forward only)",
                {"velocity", "force"},
                {"flags"},
                {kDt},
                {"out"},
                applyForceField,
                forceFieldExamples(),
                Differentiable::No}) &&
    registerOp({"vorticity_confinement",
                "out = velocity + dt * strength * N x omega, mantaflow's vorticityConfinement (forward only)",
                {"velocity"},
                {"flags"},
                {{"strength", "0.1", "confinement strength epsilon"}, kDt},
                {"out"},
                applyVorticity,
                vorticityExamples(),
                Differentiable::No});

}  // namespace
}  // namespace smokesvd::diff
