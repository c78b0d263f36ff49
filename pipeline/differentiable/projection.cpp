#include "pipeline/differentiable/projection.h"

#include <cstdio>
#include <string>

#include "nets/op_registry.h"
#include "pipeline/differentiable/example_draws.h"
#include "runtime/error.h"

namespace smokesvd::diff {
namespace {

// Runs the work recorded so far, then one solve; the stream starts a new recording after it.
void solveAfterRecorded(Stream& stream, physics::PressureSolver& solver, const Tensor& in, const Tensor& out,
                        const char* what) {
  stream.submit();
  stream.reset();
  const physics::PressureReport report = solver.project(in, out);
  if (!report.converged) {
    char detail[160];
    std::snprintf(detail, sizeof detail, "relative residual %.3g after %d iterations, tolerance %.3g", report.relativeResidual,
                  report.iterations, solver.options().tolerance);
    throw Error(std::string(what) + ": the pressure solve did not converge (" + detail +
                "); raise max_iterations or the tolerance");
  }
}

}  // namespace

Var project(Tape& tape, const std::shared_ptr<physics::PressureSolver>& solver, const Var& velocity) {
  Tensor y(tape.context(), velocity->value.shape());
  solveAfterRecorded(tape.stream(), *solver, velocity->value, y, "project");
  Var out = tape.output(y, {velocity});
  if (out->requiresGrad) {
    tape.record({out}, [solver, velocity, out](Tape& t) {
      Tensor gradVelocity(t.context(), velocity->value.shape());
      solveAfterRecorded(t.stream(), *solver, t.grad(out), gradVelocity, "project (backward)");
      t.accumulate(velocity, gradVelocity);
    });
  }
  return out;
}

namespace {

std::vector<Var> applyProject(Tape& tape, const std::vector<Var>& in, const OpAttrs& attrs) {
  const Var& velocity = in[0];
  const Var& flags = in[1];
  const GridSize grid = physics::vectorGrid(velocity->value, "project: velocity");
  physics::PressureOptions options;
  options.tolerance = attrs.number("tolerance");
  options.maxIterations = static_cast<int>(attrs.integer("max_iterations"));
  options.warmStart = false;
  if (!(options.tolerance > 0)) throw Error("op project: tolerance must be positive");
  if (options.maxIterations < 1) throw Error("op project: max_iterations must be at least 1");
  const Tensor flagTensor = flags ? flags->value : physics::closedBoxFlagsTensor(tape.context(), grid);
  auto solver = std::make_shared<physics::PressureSolver>(tape.context(), flagTensor, options);
  return {project(tape, solver, velocity)};
}

const bool registered = registerOp(
    {"project",
     "out = velocity − ∇p with A p = −div(velocity): MAC velocity [3,D,H,W], flags [D,H,W] (1 fluid, 2 obstacle, "
     "4 empty; default a closed box); backward projects the gradient (P is symmetric)",
     {"velocity"},
     {"flags"},
     {{"tolerance", "1e-5", "relative residual max|r| / max|div u| the solve stops at"},
      {"max_iterations", "200", "conjugate-gradient iterations before the solve is an error"}},
     {"out"},
     applyProject,
     // The projection is linear, so the step is large; the solves are tight to keep their error below it.
     {{.name = "closed box, odd grid",
       .inputs = {{"velocity", draw::uniform({3, 5, 6, 7})}},
       .attrs = {{"tolerance", "1e-6"}},
       .gradient = {.step = 1}},
      {.name = "obstacles and empty cells, 4-aligned grid with multigrid levels",
       .inputs = {{"velocity", draw::uniform({3, 8, 8, 8})}, {"flags", flagsDraw({8, 8, 8}, 0.05f, 0.05f)}},
       .attrs = {{"tolerance", "1e-6"}},
       .gradient = {.step = 1}}}});

}  // namespace
}  // namespace smokesvd::diff
