#include "nets/functional/elementwise.h"

#include "nets/op_registry.h"
#include "nets/ops/elementwise.h"

namespace smokesvd::fn {
namespace {

Tensor like(const Tape& tape, const Var& v) { return Tensor(tape.context(), v->value.shape()); }

// y = alpha a + beta b, with d/da = alpha g and d/db = beta g.
Var linearCombination(Tape& tape, float alpha, const Var& a, float beta, const Var& b) {
  ops::requireSameShape("elementwise op", {&a->value, &b->value});
  Tensor y = like(tape, a);
  ops::axpby(tape.stream(), alpha, a->value, beta, b->value, y);
  Var out = tape.output(y, {a, b});
  if (out->requiresGrad) {
    tape.record({out}, [a, b, out, alpha, beta](Tape& t) {
      const Tensor g = t.grad(out);
      for (const auto& [input, factor] : {std::pair{a, alpha}, std::pair{b, beta}}) {
        if (!input->requiresGrad) continue;
        if (factor == 1.0f) {
          t.accumulate(input, g);
          continue;
        }
        Tensor scaled = like(t, input);
        ops::scale(t.stream(), g, factor, scaled);
        t.accumulate(input, scaled);
      }
    });
  }
  return out;
}

}  // namespace

Var add(Tape& tape, const Var& a, const Var& b) { return linearCombination(tape, 1.0f, a, 1.0f, b); }
Var sub(Tape& tape, const Var& a, const Var& b) { return linearCombination(tape, 1.0f, a, -1.0f, b); }

Var mul(Tape& tape, const Var& a, const Var& b) {
  ops::requireSameShape("mul", {&a->value, &b->value});
  Tensor y = like(tape, a);
  ops::mul(tape.stream(), a->value, b->value, y);
  Var out = tape.output(y, {a, b});
  if (out->requiresGrad) {
    tape.record({out}, [a, b, out](Tape& t) {
      const Tensor g = t.grad(out);
      if (a->requiresGrad) {
        Tensor ga = like(t, a);
        ops::mul(t.stream(), g, b->value, ga);
        t.accumulate(a, ga);
      }
      if (b->requiresGrad) {
        Tensor gb = like(t, b);
        ops::mul(t.stream(), g, a->value, gb);
        t.accumulate(b, gb);
      }
    });
  }
  return out;
}

Var scale(Tape& tape, const Var& x, float alpha) {
  Tensor y = like(tape, x);
  ops::scale(tape.stream(), x->value, alpha, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, alpha](Tape& t) {
      Tensor gx = like(t, x);
      ops::scale(t.stream(), t.grad(out), alpha, gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

namespace {

std::vector<Var> one(Var v) { return {std::move(v)}; }

std::vector<OpExample> binaryExamples() {
  return {{.name = "odd shape", .inputs = {{"a", draw::uniform({3, 5, 7})}, {"b", draw::uniform({3, 5, 7})}},
           .gradient = {.step = 0.25}}};
}

const bool registered =
    registerOp({"add", "y = a + b (same shapes)", {"a", "b"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(add(t, in[0], in[1])); },
                binaryExamples()}) &&
    registerOp({"sub", "y = a - b (same shapes)", {"a", "b"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(sub(t, in[0], in[1])); },
                binaryExamples()}) &&
    registerOp({"mul", "y = a * b (same shapes)", {"a", "b"}, {}, {}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs&) { return one(mul(t, in[0], in[1])); },
                binaryExamples()}) &&
    registerOp({"scale", "y = alpha * x", {"x"}, {}, {{"alpha", "", "the factor"}}, {"y"},
                [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
                  return one(scale(t, in[0], static_cast<float>(attrs.number("alpha"))));
                },
                {{.name = "odd shape", .inputs = {{"x", draw::uniform({2, 3, 5})}}, .attrs = {{"alpha", "-1.5"}},
                  .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn
