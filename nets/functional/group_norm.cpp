#include "nets/functional/group_norm.h"

#include "nets/op_registry.h"
#include "nets/ops/elementwise.h"
#include "nets/ops/group_norm.h"

namespace smokesvd::fn {
namespace {

// The given parameter, or a constant [C] tensor filled with `value` when it is absent.
Var parameterOr(Tape& tape, const Var& parameter, int64_t channels, float value) {
  if (parameter) return parameter;
  Tensor constant(tape.context(), {channels});
  ops::fill(tape.stream(), constant, value);
  return variable(constant);
}

Var normalise(Tape& tape, const Var& x, const Var& gammaOrNull, const Var& betaOrNull, int groups, float eps,
              ops::NormActivation activation) {
  const ops::GroupNormShape s = ops::groupNormShape(x->value.shape(), groups);
  const Var gamma = parameterOr(tape, gammaOrNull, s.channels, 1.0f);
  const Var beta = parameterOr(tape, betaOrNull, s.channels, 0.0f);
  Tensor y(tape.context(), x->value.shape());
  Tensor stats(tape.context(), {s.batch * groups, 2});
  ops::groupNormForward(tape.stream(), x->value, gamma->value, beta->value, groups, eps, y, stats, activation);
  Var out = tape.output(y, {x, gamma, beta});
  if (out->requiresGrad) {
    tape.record({out}, [x, gamma, beta, out, stats, groups, activation](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      Tensor ggamma(t.context(), gamma->value.shape());
      Tensor gbeta(t.context(), beta->value.shape());
      ops::groupNormBackward(t.stream(), x->value, gamma->value, beta->value, stats, groups, t.grad(out), gx, ggamma,
                             gbeta, activation);
      t.accumulate(x, gx);
      t.accumulate(gamma, ggamma);
      t.accumulate(beta, gbeta);
    });
  }
  return out;
}

}  // namespace

Var groupNorm(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps) {
  return normalise(tape, x, gamma, beta, groups, eps, ops::NormActivation::None);
}

Var groupNormSilu(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps) {
  return normalise(tape, x, gamma, beta, groups, eps, ops::NormActivation::Silu);
}

namespace {

using Normalise = Var (*)(Tape&, const Var&, const Var&, const Var&, int, float);

std::function<std::vector<Var>(Tape&, const std::vector<Var>&, const OpAttrs&)> apply(Normalise op) {
  return [op](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
    return std::vector<Var>{op(t, in[0], in[1], in[2], static_cast<int>(attrs.integer("groups")),
                               static_cast<float>(attrs.number("eps")))};
  };
}

// Odd planes with an affine, 4-aligned planes without one.
std::vector<OpExample> examples() {
  return {{.name = "2D, odd planes, affine",
           .inputs = {{"x", draw::uniform({2, 4, 5, 7})}, {"gamma", draw::uniform({4}, 0.5f, 1.5f)}, {"beta", draw::uniform({4})}},
           .attrs = {{"groups", "2"}}},
          {.name = "3D, 4-aligned planes, no affine", .inputs = {{"x", draw::uniform({1, 6, 2, 3, 4})}},
           .attrs = {{"groups", "3"}, {"eps", "1e-3"}}}};
}

const std::vector<AttrSpec> kAttrs = {{"groups", "", "number of groups, divides C"},
                                      {"eps", "1e-5", "added to the variance"}};

const bool registered =
    registerOp({"group_norm", "F.group_norm(x, groups, gamma, beta, eps); gamma = 1, beta = 0 when absent", {"x"},
                {"gamma", "beta"}, kAttrs, {"y"}, apply(groupNorm), examples()}) &&
    registerOp({"group_norm_silu", "F.silu(F.group_norm(x, groups, gamma, beta, eps)); gamma = 1, beta = 0 when absent",
                {"x"}, {"gamma", "beta"}, kAttrs, {"y"}, apply(groupNormSilu), examples()});

}  // namespace
}  // namespace smokesvd::fn
