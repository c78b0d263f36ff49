#include "nets/functional/norm_silu_conv.h"

#include "nets/op_registry.h"
#include "nets/ops/group_norm.h"
#include "runtime/error.h"

namespace smokesvd::fn {

Var convOfGroupNormSilu(Tape& tape, const Var& x, const Var& gamma, const Var& beta, int groups, float eps,
                        const Var& w, const Var& bias, const ops::ConvParams& params, const Var& addend) {
  if (!gamma || !beta) throw Error("conv of group norm silu: the norm needs its gamma and beta");
  const ops::GroupNormShape s = ops::groupNormShape(x->value.shape(), groups);
  Tensor stats(tape.context(), {s.batch * groups, 2});
  ops::groupNormStats(tape.stream(), x->value, groups, eps, stats);
  Tensor y(tape.context(), ops::convOutputShape(x->value.shape(), w->value.shape(), params));
  // A convolution whose weight learns keeps its normalised, activated, padded input for the weight gradient.
  ops::PaddedInput padded;
  ops::PaddedInput* keep = w->requiresGrad && tape.gradEnabled() ? &padded : nullptr;
  ops::convForwardOfNormSilu(tape.stream(), x->value, {&stats, &gamma->value, &beta->value, groups}, w->value,
                             bias ? &bias->value : nullptr, addend ? &addend->value : nullptr, params, y, {}, keep);
  Var out = tape.output(y, {x, gamma, beta, w, bias, addend});
  if (!out->requiresGrad) return out;
  tape.record({out}, [x, gamma, beta, groups, w, bias, addend, params, stats, out, padded](Tape& t) {
    const Tensor g = t.grad(out);
    const ops::NormSiluInput norm{&stats, &gamma->value, &beta->value, groups};
    if (addend && addend->requiresGrad) t.accumulate(addend, g);
    if (w->requiresGrad) {
      Tensor dw(t.context(), w->value.shape());
      ops::convBackwardWeightOfNormSilu(t.stream(), x->value, norm, g, params, dw, {}, &padded);
      t.accumulate(w, dw);
    }
    if (bias && bias->requiresGrad) {
      Tensor db(t.context(), bias->value.shape());
      ops::convBackwardBias(t.stream(), g, db);
      t.accumulate(bias, db);
    }
    if (x->requiresGrad || gamma->requiresGrad || beta->requiresGrad) {
      Tensor activatedGrad(t.context(), x->value.shape());
      ops::convBackwardInput(t.stream(), g, w->value, params, activatedGrad);
      Tensor gx(t.context(), x->value.shape());
      Tensor ggamma(t.context(), gamma->value.shape());
      Tensor gbeta(t.context(), beta->value.shape());
      ops::groupNormBackward(t.stream(), x->value, gamma->value, beta->value, stats, groups, activatedGrad, gx, ggamma,
                             gbeta, ops::NormActivation::Silu);
      t.accumulate(x, gx);
      t.accumulate(gamma, ggamma);
      t.accumulate(beta, gbeta);
    }
  });
  return out;
}

namespace {

// Odd sizes, 2D and 3D, with and without a bias and an addend, one and several groups.
std::vector<OpExample> examples() {
  return {{.name = "2D 3x3, padding 1, bias, two groups",
           .inputs = {{"x", draw::uniform({2, 4, 5, 7})},
                      {"gamma", draw::uniform({4}, 0.5f, 1.5f)},
                      {"beta", draw::uniform({4})},
                      {"w", draw::uniform({3, 4, 3, 3})},
                      {"b", draw::uniform({3})}},
           .attrs = {{"groups", "2"}, {"padding", "1"}}},
          {.name = "3D 3x3x3, stride 2, padding 1, plus an addend, one group",
           .inputs = {{"x", draw::uniform({1, 3, 3, 5, 6})},
                      {"gamma", draw::uniform({3}, 0.5f, 1.5f)},
                      {"beta", draw::uniform({3})},
                      {"w", draw::uniform({2, 3, 3, 3, 3})},
                      {"addend", draw::uniform({1, 2, 2, 3, 3})}},
           .attrs = {{"groups", "1"}, {"stride", "2"}, {"padding", "1"}}}};
}

const bool registered = registerOp(
    {"group_norm_silu_conv",
     "y = addend + conv(silu(F.group_norm(x, groups, gamma, beta, eps)), w) + b; x [N,C,(D,)H,W], w [K,C,k...]",
     {"x", "gamma", "beta", "w"},
     {"b", "addend"},
     {{"groups", "", "number of groups, divides C"},
      {"eps", "1e-5", "added to the variance"},
      {"stride", "1", "the same along every axis"},
      {"padding", "0", "zero padding, the same along every axis"}},
     {"y"},
     [](Tape& t, const std::vector<Var>& in, const OpAttrs& a) {
       ops::ConvParams params;
       params.stride = static_cast<int>(a.integer("stride"));
       params.padding = static_cast<int>(a.integer("padding"));
       return std::vector<Var>{convOfGroupNormSilu(t, in[0], in[1], in[2], static_cast<int>(a.integer("groups")),
                                                   static_cast<float>(a.number("eps")), in[3], in[4], params,
                                                   in.size() > 5 ? in[5] : nullptr)};
     },
     examples()});

}  // namespace
}  // namespace smokesvd::fn
