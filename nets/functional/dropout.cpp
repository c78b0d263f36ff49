#include "nets/functional/dropout.h"

#include "nets/op_registry.h"
#include "nets/ops/dropout.h"
#include "runtime/error.h"

namespace smokesvd::fn {

Var dropout(Tape& tape, const Var& x, float p, uint64_t seed, bool training) {
  if (!(p >= 0.0f && p <= 1.0f)) throw Error("dropout: p = " + std::to_string(p) + " is not in [0, 1]");
  if (!training || !tape.gradEnabled()) return x;
  Tensor y(tape.context(), x->value.shape());
  ops::dropout(tape.stream(), x->value, p, seed, y);
  Var out = tape.output(y, {x});
  if (out->requiresGrad) {
    tape.record({out}, [x, out, p, seed](Tape& t) {
      Tensor gx(t.context(), x->value.shape());
      ops::dropout(t.stream(), t.grad(out), p, seed, gx);
      t.accumulate(x, gx);
    });
  }
  return out;
}

namespace {

const bool registered = registerOp(
    {"dropout", "y = mask(seed) * x / (1 - p) in training, y = x otherwise", {"x"}, {},
     {{"p", "0.5", "drop probability in [0, 1]"}, {"seed", "0", "mask seed (integer)"},
      {"training", "1", "1: drop, 0: identity"}},
     {"y"}, [](Tape& t, const std::vector<Var>& in, const OpAttrs& attrs) {
       return std::vector<Var>{dropout(t, in[0], static_cast<float>(attrs.number("p")),
                                       static_cast<uint64_t>(attrs.integer("seed")), attrs.integer("training") != 0)};
     },
     {{.name = "training", .inputs = {{"x", draw::uniform({2, 3, 5})}}, .attrs = {{"p", "0.4"}, {"seed", "99"}},
       .gradient = {.step = 0.25}},
      {.name = "inference", .inputs = {{"x", draw::uniform({3, 7})}}, .attrs = {{"training", "0"}},
       .gradient = {.step = 0.25}}}});

}  // namespace
}  // namespace smokesvd::fn
